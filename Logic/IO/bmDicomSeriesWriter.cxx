#include "bmDicomSeriesWriter.h"

#include "bmAtomicFile.h" // TemporarySibling

#include <gdcmImageChangeTransferSyntax.h>
#include <gdcmImageWriter.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace bm {

namespace {

void Put(gdcm::DataSet& ds, uint16_t g, uint16_t e, gdcm::VR vr, std::string value) {
  if (value.size() % 2)
    value.push_back(vr == gdcm::VR::UI ? '\0' : ' ');
  gdcm::DataElement de(gdcm::Tag(g, e));
  de.SetVR(vr);
  de.SetByteValue(value.data(), uint32_t(value.size()));
  ds.Replace(de);
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  std::string s = buf;
  return s.size() > 16 ? s.substr(0, 16) : s; // DS values are at most 16 characters
}

gdcm::TransferSyntax::TSType Syntax(const std::string& name) {
  if (name.empty() || name == "explicit")
    return gdcm::TransferSyntax::ExplicitVRLittleEndian;
  if (name == "rle")
    return gdcm::TransferSyntax::RLELossless;
  if (name == "jpeg-lossless")
    return gdcm::TransferSyntax::JPEGLosslessProcess14_1;
  if (name == "jpeg-ls")
    return gdcm::TransferSyntax::JPEGLSLossless;
  if (name == "jpeg2000")
    return gdcm::TransferSyntax::JPEG2000Lossless;
  throw std::runtime_error("unknown transfer syntax '" + name +
                           "' (explicit, rle, jpeg-lossless, jpeg-ls or jpeg2000)");
}

} // namespace

std::string WriteDicomSeries(const CTImage& ct, const std::string& folder,
                             const DicomWriteOptions& opt, const Progress& progress) {
  const auto ts = Syntax(opt.transferSyntax);
  fs::path out(folder);
  if (fs::exists(out) && (!fs::is_directory(out) || !fs::is_empty(out)))
    throw std::runtime_error("'" + folder +
                             "' already exists and is not an empty folder: not overwriting it");
  fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  if (!fs::is_directory(parent))
    throw std::runtime_error("folder '" + parent.string() + "' does not exist");

  const HUImage* img = ct.hu.GetPointer();
  const auto size = img->GetLargestPossibleRegion().GetSize();
  const auto sp = img->GetSpacing();
  const auto D = img->GetDirection();
  const size_t nx = size[0], ny = size[1], nz = size[2];

  gdcm::Trace::WarningOff(); // GDCM warns about tags the writer fills in itself
  gdcm::UIDGenerator uid;
  const std::string studyUID = opt.studyUID.empty() ? uid.Generate() : opt.studyUID;
  const std::string seriesUID = opt.seriesUID.empty() ? uid.Generate() : opt.seriesUID;
  const std::string frameUID = uid.Generate();
  double iop[6] = {D[0][0], D[1][0], D[2][0], D[0][1], D[1][1], D[2][1]};

  const fs::path tmp =
      fs::path(TemporarySibling((parent / (out.filename().string() + ".d")).string()));
  fs::create_directory(tmp);
  try {
    std::vector<uint16_t> pixels(nx * ny);
    for (size_t k = 0; k < nz; ++k) {
      progress(double(k) / nz, "writing DICOM series");
      const float* src = img->GetBufferPointer() + k * nx * ny;
      for (size_t v = 0; v < nx * ny; ++v)
        pixels[v] = uint16_t(std::clamp(std::lround(double(src[v])) + 1024L, 0L, 65535L));
      itk::Index<3> index{{0, 0, long(k)}};
      itk::Point<double, 3> pos;
      img->TransformIndexToPhysicalPoint(index, pos);

      gdcm::SmartPointer<gdcm::Image> im = new gdcm::Image;
      im->SetNumberOfDimensions(2);
      im->SetDimension(0, unsigned(nx));
      im->SetDimension(1, unsigned(ny));
      im->SetPixelFormat(gdcm::PixelFormat::UINT16);
      im->SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
      im->SetSpacing(0, sp[0]);
      im->SetSpacing(1, sp[1]);
      im->SetSpacing(2, sp[2]);
      for (unsigned a = 0; a < 3; ++a)
        im->SetOrigin(a, pos[a]); // SetOrigin(double*) keeps only 2 for 2-D
      im->SetDirectionCosines(iop);
      im->SetIntercept(-1024.0);
      im->SetSlope(1.0);
      gdcm::DataElement pixeldata(gdcm::Tag(0x7fe0, 0x0010));
      pixeldata.SetByteValue(reinterpret_cast<const char*>(pixels.data()),
                             uint32_t(pixels.size() * 2));
      im->SetDataElement(pixeldata);
      im->SetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);

      gdcm::ImageWriter writer;
      if (ts != gdcm::TransferSyntax::ExplicitVRLittleEndian) {
        gdcm::ImageChangeTransferSyntax change;
        change.SetTransferSyntax(ts);
        change.SetInput(*im);
        if (!change.Change())
          throw std::runtime_error("GDCM cannot encode slice " + std::to_string(k + 1) + " as " +
                                   opt.transferSyntax);
        writer.SetImage(change.GetOutput());
      } else {
        writer.SetImage(*im);
      }
      gdcm::DataSet& ds = writer.GetFile().GetDataSet();
      Put(ds, 0x0008, 0x0016, gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.2"); // CT Image Storage
      Put(ds, 0x0008, 0x0018, gdcm::VR::UI, uid.Generate());
      Put(ds, 0x0008, 0x0008, gdcm::VR::CS, "ORIGINAL\\PRIMARY\\AXIAL");
      Put(ds, 0x0008, 0x0060, gdcm::VR::CS, opt.modality);
      Put(ds, 0x0008, 0x0070, gdcm::VR::LO, "BoneMachining");
      Put(ds, 0x0008, 0x103e, gdcm::VR::LO, opt.seriesDescription);
      Put(ds, 0x0010, 0x0010, gdcm::VR::PN, opt.patientName);
      Put(ds, 0x0010, 0x0020, gdcm::VR::LO, opt.patientID);
      Put(ds, 0x0018, 0x0050, gdcm::VR::DS, Num(sp[2]));
      Put(ds, 0x0020, 0x000d, gdcm::VR::UI, studyUID);
      Put(ds, 0x0020, 0x000e, gdcm::VR::UI, seriesUID);
      Put(ds, 0x0020, 0x0052, gdcm::VR::UI, frameUID);
      Put(ds, 0x0020, 0x0011, gdcm::VR::IS, "1");
      Put(ds, 0x0020, 0x0013, gdcm::VR::IS, std::to_string(k + 1));
      Put(ds, 0x0028, 0x1054, gdcm::VR::LO, "HU");
      char name[32];
      std::snprintf(name, sizeof name, "IM%05zu.dcm", k + 1);
      const fs::path file = tmp / name;
      // GDCM asserts (aborts) when its output stream fails, e.g. on a full disk: it writes into
      // memory, and the bytes go to the file here, where a failed write is an error.
      std::ostringstream bytes;
      writer.SetStream(bytes);
      if (!writer.Write())
        throw std::runtime_error("GDCM cannot encode slice " + std::to_string(k + 1) +
                                 " of the DICOM series");
      const std::string encoded = bytes.str();
      std::ofstream os(file, std::ios::binary);
      os.write(encoded.data(), std::streamsize(encoded.size()));
      os.close();
      if (!os)
        throw std::runtime_error("cannot write DICOM file '" + file.string() + "' (" +
                                 std::strerror(errno) + "; is the disk full?)");
    }
    if (fs::exists(out))
      fs::remove(out); // an empty folder (checked above)
    fs::rename(tmp, out);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  progress(1.0, "writing DICOM series");
  return seriesUID;
}

} // namespace bm
