// bmVTKImageVolume.cxx - see bmVTKImageVolume.h.
#include "bmVTKImageVolume.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkSmartPointer.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStructuredPointsReader.h"
#include "vtkXMLImageDataReader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <filesystem>
#include <stdexcept>

namespace bm {

namespace {

/// The first error or warning a VTK reader reports (VTK readers report damaged files, e.g. binary
/// data cut short, as events and still produce an image of whatever they read).
struct ReaderComplaint {
  std::string text;
  vtkNew<vtkCallbackCommand> command;
  explicit ReaderComplaint(vtkAlgorithm* reader) {
    command->SetClientData(this);
    command->SetCallback([](vtkObject*, unsigned long, void* self, void* message) {
      auto* c = static_cast<ReaderComplaint*>(self);
      if (c->text.empty() && message)
        c->text = static_cast<const char*>(message);
    });
    reader->AddObserver(vtkCommand::ErrorEvent, command);
    reader->AddObserver(vtkCommand::WarningEvent, command);
  }
};

/// Everything VTK prints while it lives (warnings without an object, such as the legacy reader's
/// "Error reading ascii data", reach only the output window): the first error or warning is kept
/// and the previous window is restored at the end.
class CaptureWindow : public vtkOutputWindow {
public:
  static CaptureWindow* New();
  vtkTypeMacro(CaptureWindow, vtkOutputWindow);
  std::string text;
  void DisplayText(const char*) override {}
  void DisplayErrorText(const char* t) override { Keep(t); }
  void DisplayWarningText(const char* t) override { Keep(t); }
  void DisplayGenericWarningText(const char* t) override { Keep(t); }

private:
  void Keep(const char* t) {
    if (text.empty() && t)
      text = t;
  }
};
vtkStandardNewMacro(CaptureWindow);

struct CapturedOutput {
  vtkSmartPointer<vtkOutputWindow> previous = vtkOutputWindow::GetInstance();
  vtkNew<CaptureWindow> window;
  CapturedOutput() { vtkOutputWindow::SetInstance(window); }
  ~CapturedOutput() { vtkOutputWindow::SetInstance(previous); }
};

/// The numbers of attribute `name` of the first `<ImageData` element of a .vti file (empty when
/// absent): VTK's XML reader reads "nan" or a word as 0 or leaves the default, silently.
void CheckVtiNumbers(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(1 << 16, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  const size_t at = head.find("<ImageData");
  if (at == std::string::npos)
    return;
  const size_t end = head.find('>', at);
  const std::string element =
      head.substr(at, end == std::string::npos ? std::string::npos : end - at);
  for (const char* name : {"Spacing", "Origin", "Direction", "WholeExtent"}) {
    const size_t a = element.find(std::string(" ") + name + "=\"");
    if (a == std::string::npos)
      continue;
    const size_t from = a + std::strlen(name) + 3, to = element.find('"', from);
    std::istringstream words(element.substr(from, to - from));
    std::string word;
    while (words >> word) {
      char* stop = nullptr;
      const double v = std::strtod(word.c_str(), &stop);
      if (*stop != '\0' || !std::isfinite(v))
        throw std::runtime_error("'" + path + "': ImageData " + name + " holds '" + word +
                                 "', not a finite number");
    }
  }
}

std::string Trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
    s.pop_back();
  return s;
}

} // namespace

const std::vector<std::string>& VTKImageExtensions() {
  static const std::vector<std::string> kExtensions{".vti", ".vtk"};
  return kExtensions;
}

bool IsVTKImageFile(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext)
    c = char(std::tolower(static_cast<unsigned char>(c)));
  const auto& known = VTKImageExtensions();
  return std::find(known.begin(), known.end(), ext) != known.end();
}

/// Refuses an image extent that is inverted or larger than 2^31 points, before the reader
/// allocates it (VTK aborts when an allocation fails).
static void CheckExtent(vtkAlgorithm* reader, const std::string& path) {
  int e[6] = {0, -1, 0, -1, 0, -1};
  reader->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), e);
  double points = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = double(e[2 * a + 1]) - double(e[2 * a]) + 1;
    if (!(n >= 1))
      throw std::runtime_error("'" + path + "' has an empty or inverted extent along axis " +
                               std::to_string(a));
    points *= n;
  }
  if (points > 2147483647.0)
    throw std::runtime_error("'" + path + "' declares " + std::to_string(points) +
                             " points, more than 2^31");
}

vtkSmartPointer<vtkImageData> ReadVTKImageFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error("cannot read '" + path + "': no such file");
  vtkSmartPointer<vtkImageData> image;
  const std::string ext = std::filesystem::path(path).extension().string();
  auto read = [&](vtkAlgorithm* reader) {
    CapturedOutput output;
    ReaderComplaint complaint(reader);
    reader->UpdateInformation();
    if (!complaint.text.empty())
      throw std::runtime_error("cannot read '" + path + "': " + Trimmed(complaint.text));
    CheckExtent(reader, path);
    reader->Update();
    if (complaint.text.empty())
      complaint.text = output.window->text;
    if (!complaint.text.empty())
      throw std::runtime_error("cannot read '" + path + "': " + Trimmed(complaint.text));
    image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  };
  if (ext == ".vti" || ext == ".VTI") {
    CheckVtiNumbers(path);
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.c_str());
    read(reader);
  } else { // legacy .vtk: structured points only (its reader reports what it cannot read)
    vtkNew<vtkStructuredPointsReader> reader;
    reader->SetFileName(path.c_str());
    read(reader);
  }
  if (!image || image->GetNumberOfPoints() == 0)
    throw std::runtime_error("cannot read '" + path + "' as a VTK image (structured points)");
  const double* sp = image->GetSpacing();
  const double* o = image->GetOrigin();
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(sp[a]) || std::abs(sp[a]) < 1e-4 || std::abs(sp[a]) > 1e4)
      throw std::runtime_error("'" + path + "' has a voxel spacing of " + std::to_string(sp[a]) +
                               " mm along axis " + std::to_string(a) +
                               "; it must be finite, at least 0.0001 mm and at most 10 000 mm");
    if (!std::isfinite(o[a]))
      throw std::runtime_error("'" + path + "' has a non-finite origin");
  }
  vtkMatrix3x3* d = image->GetDirectionMatrix();
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(d->GetData()[i]))
      throw std::runtime_error("'" + path + "' has a non-finite direction");
  vtkDataArray* values = image->GetPointData()->GetScalars();
  if (!values && image->GetPointData()->GetNumberOfArrays() > 0)
    values = image->GetPointData()->GetArray(0);
  if (values && values->GetNumberOfTuples() != image->GetNumberOfPoints())
    throw std::runtime_error("'" + path + "' holds " + std::to_string(values->GetNumberOfTuples()) +
                             " values for " + std::to_string(image->GetNumberOfPoints()) +
                             " points: truncated or corrupt");
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
  const int type = values->GetDataType();
  view.storedBits = 8 * values->GetDataTypeSize();
  view.storedInteger = type != VTK_FLOAT && type != VTK_DOUBLE;
}

#endif

} // namespace bm
