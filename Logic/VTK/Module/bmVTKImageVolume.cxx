// bmVTKImageVolume.cxx - see bmVTKImageVolume.h.
#include "bmVTKImageVolume.h"

#include "vtkDataArray.h"
#include "vtkDataSetReader.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkXMLImageDataReader.h"

#include <filesystem>
#include <stdexcept>

namespace bm {

bool IsVTKImageFile(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".vti" || ext == ".vtk" || ext == ".VTI" || ext == ".VTK";
}

vtkSmartPointer<vtkImageData> ReadVTKImageFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error("cannot read '" + path + "': no such file");
  vtkSmartPointer<vtkImageData> image;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".vti" || ext == ".VTI") {
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    image = reader->GetOutput();
  } else {
    vtkNew<vtkDataSetReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    image = vtkImageData::SafeDownCast(reader->GetOutput());
  }
  if (!image || image->GetNumberOfPoints() == 0)
    throw std::runtime_error("cannot read '" + path + "' as a VTK image (structured points)");
  return image;
}

#ifdef BM_WITH_IO
void VolumeFromVTKImage(vtkImageData* image, const std::string& source, VTKImageVolume& out) {
  vtkDataArray* values = image->GetPointData()->GetScalars();
  if (!values && image->GetPointData()->GetNumberOfArrays() > 0)
    values = image->GetPointData()->GetArray(0);
  if (!values)
    throw std::runtime_error(source + " has no point scalars (the CT's values)");
  CTVolumeView& view = out.view;
  view = CTVolumeView();
  int ext[6];
  image->GetExtent(ext);
  const double* sp = image->GetSpacing();
  const double* o = image->GetOrigin();
  vtkMatrix3x3* d = image->GetDirectionMatrix();
  for (int a = 0; a < 3; ++a) {
    view.dims[a] = ext[2 * a + 1] - ext[2 * a] + 1;
    view.spacing[a] = sp[a];
    for (int c = 0; c < 3; ++c)
      view.direction[size_t(3 * a + c)] = d->GetElement(a, c);
  }
  for (int a = 0; a < 3; ++a) // world of the first voxel: origin + D (ext_min * spacing)
    view.origin[a] = o[a] + d->GetElement(a, 0) * ext[0] * sp[0] +
                     d->GetElement(a, 1) * ext[2] * sp[1] + d->GetElement(a, 2) * ext[4] * sp[2];
  const vtkIdType n = values->GetNumberOfTuples();
  out.values.resize(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    out.values[size_t(i)] = float(values->GetComponent(i, 0));
  view.values = out.values.data();
  view.source = source;
}

#endif

} // namespace bm
  const int type = values->GetDataType();
  view.storedBits = 8 * values->GetDataTypeSize();
  view.storedInteger = type != VTK_FLOAT && type != VTK_DOUBLE;
