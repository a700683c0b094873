// bmCTReaderVolume.cxx - a CT from a single volume file (NRRD, MetaImage, NIfTI) through ITK,
// its header checked first (bmHeaderCheck.h) and its geometry after (bmCTReaderInternal.h).
#include "bmCTReaderInternal.h"

#include "bmCTFileTypes.h"
#include "bmHeaderCheck.h"

#include <itkImageFileReader.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fs = std::filesystem;

namespace bm::ctreader {

ReadOutcome ReadVolumeFile(const fs::path& file, const ReadOptions& opt, const Progress& progress) {
  std::string name = ToLower(file.filename().string());
  auto endsWith = [&](const std::string& s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  itk::ImageIOBase::Pointer io;
  std::string format;
  if (endsWith(".nrrd") || endsWith(".nhdr")) {
    io = itk::NrrdImageIO::New();
    format = "NRRD";
  } else if (endsWith(".mha") || endsWith(".mhd")) {
    io = itk::MetaImageIO::New();
    format = "MetaImage";
  } else if (endsWith(".nii") || endsWith(".nii.gz")) {
    io = itk::NiftiImageIO::New();
    format = "NIfTI";
  } else {
    throw std::runtime_error("'" + file.string() +
                             "': unknown file type (expected a DICOM folder or " +
                             ExtensionList(CTFileExtensions()) + ")");
  }
  // Our own header check first: ITK would allocate, follow data file paths or abort on these.
  const VolumeHeader header = CheckVolumeHeader(
      file, format, {opt.maxMemoryBytes, opt.allowDataOutsideFolder, 1, opt.extraBytesPerVoxel});
  if (!io->CanReadFile(file.c_str()))
    throw std::runtime_error("'" + file.string() + "' cannot be read as " + format +
                             " (corrupt or not " + format + ")");
  io->SetFileName(file.string());
  io->ReadImageInformation();
  if (io->GetNumberOfDimensions() != 3)
    throw std::runtime_error("'" + file.string() + "' is a " +
                             std::to_string(io->GetNumberOfDimensions()) +
                             "-D image; a CT volume must be 3-D");
  if (io->GetNumberOfComponents() != 1)
    throw std::runtime_error("'" + file.string() + "' has " +
                             std::to_string(io->GetNumberOfComponents()) +
                             " components per voxel; a CT has one");
  uint64_t voxels = 1;
  for (unsigned a = 0; a < 3; ++a) {
    double s = io->GetSpacing(a);
    if (!(s > 0) || !std::isfinite(s))
      throw std::runtime_error("'" + file.string() +
                               "' has a zero or invalid voxel spacing along axis " +
                               std::to_string(a));
    if (!std::isfinite(io->GetOrigin(a)))
      throw std::runtime_error("'" + file.string() + "' has a non-finite origin");
    for (double d : io->GetDirection(a))
      if (!std::isfinite(d))
        throw std::runtime_error("'" + file.string() + "' has a non-finite direction");
    const std::vector<double> axis = io->GetDirection(a);
    double len = 0;
    for (double d : axis)
      len += d * d;
    len = std::sqrt(len);
    if (std::abs(len - 1) > kOrientationTolerance) {
      std::ostringstream os;
      os << "'" << file.string() << "': its direction axis " << a << " has length " << len
         << ", not 1 (a scaled direction matrix or TransformMatrix: the voxel size and "
            "orientation are ambiguous)";
      throw std::runtime_error(os.str());
    }
    for (unsigned b = 0; b < a; ++b) {
      const std::vector<double> other = io->GetDirection(b);
      double dot = 0;
      for (size_t i = 0; i < 3 && i < axis.size() && i < other.size(); ++i)
        dot += axis[i] * other[i];
      if (std::abs(dot) > kOrientationTolerance) {
        std::ostringstream os;
        os << "'" << file.string() << "': its direction axes " << b << " and " << a << " are "
           << std::acos(std::clamp(dot, -1.0, 1.0)) * 180 / M_PI
           << " deg apart, not 90 (a skewed direction matrix)";
        throw std::runtime_error(os.str());
      }
    }
    if (io->GetDimensions(a) != header.dims[a])
      throw std::runtime_error("'" + file.string() +
                               "': the header's sizes do not parse "
                               "consistently");
    voxels *= io->GetDimensions(a);
  }
  std::string mod;
  if (format == "MetaImage") {
    if (itk::ExposeMetaData<std::string>(io->GetMetaDataDictionary(), "Modality", mod) &&
        !mod.empty() && mod != "MET_MOD_CT" && !opt.allowNonCT)
      throw std::runtime_error("'" + file.string() + "' has modality " + mod + ", not CT");
  }
  CheckMemoryBudget(voxels * sizeof(float), opt.maxMemoryBytes,
                    "the CT (" + std::to_string(io->GetDimensions(0)) + " x " +
                        std::to_string(io->GetDimensions(1)) + " x " +
                        std::to_string(io->GetDimensions(2)) + " voxels)");
  auto reader = itk::ImageFileReader<HUImage>::New();
  reader->SetImageIO(io);
  reader->SetFileName(file.string());
  RunFilter(reader, progress, "reading volume");
  ReadOutcome out;
  CTImage& ct = out.ct;
  ct.hu = reader->GetOutput();
  ct.hu->DisconnectPipeline();
  ct.source = file.string();
  ct.format = format;
  ct.numFiles = 1;
  out.evidence.modality = mod == "MET_MOD_CT" ? "CT" : mod;
  out.evidence.hasRescale = header.hasRescale;
  out.evidence.storedBits = 8 * header.componentBytes;
  out.evidence.storedInteger = header.integerType;
  return out;
}

} // namespace bm::ctreader
