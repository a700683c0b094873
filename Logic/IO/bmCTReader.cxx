#include "bmCTReader.h"

#include "bmInvesaliusReader.h"

#include <gdcmExplicitDataElement.h>
#include <gdcmImplicitDataElement.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDs.h>
#include <gdcmStringFilter.h>
#include <gdcmTransferSyntax.h>

#include <itkGDCMImageIO.h>
#include <itkImageFileReader.h>
#include <itkImageRegionConstIterator.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace bm {

uint64_t DefaultMemoryLimit() {
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0)
    return uint64_t(4) << 30;
  return uint64_t(double(pages) * double(page) * 0.75);
}

namespace {

std::string Trim(std::string s) {
  while (!s.empty() && (std::isspace((unsigned char)s.back()) || s.back() == '\0'))
    s.pop_back();
  size_t i = 0;
  while (i < s.size() && std::isspace((unsigned char)s[i]))
    ++i;
  return s.substr(i);
}

std::string ToLower(std::string s) {
  for (auto& c : s)
    c = char(std::tolower((unsigned char)c));
  return s;
}

std::string MiB(uint64_t bytes) {
  std::ostringstream os;
  os << (bytes + (1u << 20) - 1) / (1u << 20) << " MiB";
  return os.str();
}

/// "a\b\c" -> numbers; empty when any part does not parse.
std::vector<double> ParseNumbers(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string part;
  while (std::getline(ss, part, '\\')) {
    part = Trim(part);
    if (part.empty())
      return {};
    try {
      size_t used = 0;
      v.push_back(std::stod(part, &used));
      if (used != part.size())
        return {};
    } catch (...) {
      return {};
    }
  }
  return v;
}

} // namespace

void CheckMemoryBudget(uint64_t bytes, uint64_t limitBytes, const std::string& what) {
  uint64_t limit = limitBytes ? limitBytes : DefaultMemoryLimit();
  if (bytes > limit)
    throw std::runtime_error(what + " needs " + MiB(bytes) + " of memory, more than the " +
                             MiB(limit) +
                             " allowed (raise the memory limit or crop the volume first)");
}

void UpdateHURange(CTImage& ct) {
  const float* p = ct.hu->GetBufferPointer();
  size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (size_t i = 0; i < n; ++i) {
    lo = std::min(lo, p[i]);
    hi = std::max(hi, p[i]);
  }
  ct.huMin = lo;
  ct.huMax = hi;
  if (ct.huMax < 200)
    ct.warnings.push_back("the highest value is " + std::to_string(int(hi)) +
                          ", below any bone in Hounsfield units: check that this is a CT in HU");
  else if (ct.huMin >= 0 && ct.huMax > 1000)
    ct.warnings.push_back(
        "no value is below 0 (air is near -1000 HU, fat near -100 HU): the values may be "
        "stored pixel values rather than Hounsfield units");
}

namespace {

// ---------------------------------------------------------------------------------------------
// DICOM

/// Files in a DICOM folder that are never DICOM: skipped without complaint.
bool IgnorableFile(const fs::path& p) {
  std::string name = p.filename().string();
  if (name.empty() || name[0] == '.')
    return true;
  std::string lower = ToLower(name);
  if (lower == "dicomdir" || lower == "lockfile" || lower == "version")
    return true;
  static const std::set<std::string> exts = {".txt", ".md",  ".json", ".xml", ".html", ".htm",
                                             ".pdf", ".jpg", ".jpeg", ".png", ".ini",  ".inf",
                                             ".exe", ".bat", ".sh",   ".csv", ".log"};
  return exts.count(ToLower(p.extension().string())) > 0;
}

struct SliceHeader {
  fs::path file;
  std::string seriesUID, modality, description, transferSyntax, frames;
  int rows = 0, cols = 0;
  std::vector<double> pixelSpacing, ipp, iop;
  bool hasPixelData = false;
  double position = 0; // along the slice normal, mm
};

SliceHeader ReadSliceHeader(const fs::path& file) {
  gdcm::Trace::WarningOff(); // problems are reported as errors below, not as GDCM console warnings
  gdcm::Reader reader;
  reader.SetFileName(file.c_str());
  if (!reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010), std::set<gdcm::Tag>{}))
    throw std::runtime_error(
        "'" + file.string() +
        "' is not a readable DICOM file (corrupt, truncated header, or not DICOM)");
  const gdcm::File& f = reader.GetFile();
  const gdcm::DataSet& ds = f.GetDataSet();
  gdcm::StringFilter sf;
  sf.SetFile(f);
  auto str = [&](uint16_t g, uint16_t e) {
    gdcm::Tag t(g, e);
    return ds.FindDataElement(t) ? Trim(sf.ToString(t)) : std::string();
  };
  SliceHeader h;
  h.file = file;
  h.seriesUID = str(0x0020, 0x000e);
  h.modality = str(0x0008, 0x0060);
  h.description = str(0x0008, 0x103e);
  h.frames = str(0x0028, 0x0008);
  std::string rows = str(0x0028, 0x0010), cols = str(0x0028, 0x0011);
  h.rows = rows.empty() ? 0 : std::atoi(rows.c_str());
  h.cols = cols.empty() ? 0 : std::atoi(cols.c_str());
  h.pixelSpacing = ParseNumbers(str(0x0028, 0x0030));
  h.ipp = ParseNumbers(str(0x0020, 0x0032));
  h.iop = ParseNumbers(str(0x0020, 0x0037));
  const gdcm::TransferSyntax ts = f.GetHeader().GetDataSetTransferSyntax();
  {
    gdcm::UIDs name;
    const char* uid = gdcm::TransferSyntax::GetTSString(ts);
    h.transferSyntax =
        uid && name.SetFromUID(uid) && name.GetName() ? name.GetName() : (uid ? uid : "");
  }
  // GDCM reads a file cut short inside its pixel data with only a warning (and pads it), so check
  // that the file holds every byte its header and elements declare, and for native (uncompressed)
  // pixels that the Pixel Data element is as long as rows x columns x bits x samples x frames.
  const bool hasPixels = ds.FindDataElement(gdcm::Tag(0x7fe0, 0x0010));
  uint64_t declared =
      f.GetHeader().GetFullLength() + (ts.IsExplicit() ? ds.GetLength<gdcm::ExplicitDataElement>()
                                                       : ds.GetLength<gdcm::ImplicitDataElement>());
  if (uint64_t(fs::file_size(file)) < declared)
    throw std::runtime_error("'" + file.string() + "' is truncated: its elements declare " +
                             std::to_string(declared) + " bytes, the file holds " +
                             std::to_string(fs::file_size(file)));
  if (hasPixels && !ts.IsEncapsulated() && h.rows > 0 && h.cols > 0) {
    std::string bits = str(0x0028, 0x0100), spp = str(0x0028, 0x0002);
    uint64_t need = uint64_t(h.rows) * uint64_t(h.cols) *
                    uint64_t(bits.empty() ? 16 : std::atoi(bits.c_str())) / 8 *
                    uint64_t(spp.empty() ? 1 : std::max(1, std::atoi(spp.c_str()))) *
                    uint64_t(h.frames.empty() ? 1 : std::max(1, std::atoi(h.frames.c_str())));
    const gdcm::DataElement& px = ds.GetDataElement(gdcm::Tag(0x7fe0, 0x0010));
    if (!px.GetVL().IsUndefined() && uint64_t(px.GetVL()) < need)
      throw std::runtime_error("'" + file.string() + "' is truncated: its pixel data hold " +
                               std::to_string(uint64_t(px.GetVL())) + " bytes of the " +
                               std::to_string(need) + " its size needs");
  }
  // ReadUpToTag stops before the pixel data, so "has pixels" = it is an image (rows and columns).
  h.hasPixelData = h.rows > 0 && h.cols > 0;
  return h;
}

struct ScannedFolder {
  std::map<std::string, std::vector<SliceHeader>> series; // by SeriesInstanceUID
};

ScannedFolder ScanFolder(const fs::path& dir, const Progress& progress) {
  if (!fs::exists(dir))
    throw std::runtime_error("'" + dir.string() + "' does not exist");
  if (!fs::is_directory(dir))
    throw std::runtime_error("'" + dir.string() + "' is not a folder");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && !IgnorableFile(e.path()))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw std::runtime_error("folder '" + dir.string() + "' is empty: no DICOM files to read");
  ScannedFolder out;
  for (size_t i = 0; i < files.size(); ++i) {
    if (i % 16 == 0)
      progress(double(i) / files.size(), "scanning DICOM headers");
    SliceHeader h = ReadSliceHeader(files[i]);
    if (!h.hasPixelData)
      continue; // presentation states, reports, ... : not images
    if (h.seriesUID.empty())
      throw std::runtime_error("'" + files[i].string() + "' has no SeriesInstanceUID (0020,000E)");
    out.series[h.seriesUID].push_back(std::move(h));
  }
  if (out.series.empty())
    throw std::runtime_error("folder '" + dir.string() + "' holds no DICOM image series (" +
                             std::to_string(files.size()) + " files, none an image)");
  return out;
}

std::string DescribeSeries(const std::vector<DicomSeriesInfo>& list) {
  std::ostringstream os;
  for (const auto& s : list)
    os << "\n  " << s.uid << "  " << (s.modality.empty() ? "?" : s.modality) << ", " << s.numFiles
       << " files" << (s.description.empty() ? "" : ", \"" + s.description + "\"");
  return os.str();
}

std::vector<DicomSeriesInfo> Summaries(const ScannedFolder& sf) {
  std::vector<DicomSeriesInfo> v;
  for (const auto& [uid, slices] : sf.series)
    v.push_back({uid, slices.front().modality, slices.front().description, int(slices.size())});
  return v;
}

CTImage ReadDicomFolder(const fs::path& dir, const ReadOptions& opt, const Progress& progress) {
  ScannedFolder scanned = ScanFolder(dir, progress.Range(0, 0.1));
  std::vector<SliceHeader>* chosen = nullptr;
  if (!opt.seriesUID.empty()) {
    auto it = scanned.series.find(opt.seriesUID);
    if (it == scanned.series.end())
      throw std::runtime_error("series " + opt.seriesUID + " is not in '" + dir.string() +
                               "'; the folder holds:" + DescribeSeries(Summaries(scanned)));
    chosen = &it->second;
  } else if (scanned.series.size() > 1) {
    throw std::runtime_error("folder '" + dir.string() + "' holds " +
                             std::to_string(scanned.series.size()) +
                             " DICOM series; choose one by its SeriesInstanceUID (--series UID):" +
                             DescribeSeries(Summaries(scanned)));
  } else {
    chosen = &scanned.series.begin()->second;
  }
  std::vector<SliceHeader>& slices = *chosen;
  const SliceHeader& first = slices.front();
  const std::string where = "DICOM series " + first.seriesUID + " in '" + dir.string() + "'";

  if (first.modality != "CT" && !opt.allowNonCT)
    throw std::runtime_error(where + " has modality '" + first.modality +
                             "', not CT: only CT gives Hounsfield units for bone segmentation");
  for (const auto& s : slices) {
    const std::string f = "'" + s.file.filename().string() + "' of " + where;
    if (!s.frames.empty() && std::atoi(s.frames.c_str()) > 1)
      throw std::runtime_error(f +
                               " is a multi-frame image; only single-frame slices are supported");
    if (s.pixelSpacing.size() != 2)
      throw std::runtime_error(f +
                               " has no valid PixelSpacing (0028,0030): the voxel size is unknown");
    if (!(s.pixelSpacing[0] > 0 && s.pixelSpacing[1] > 0) || !std::isfinite(s.pixelSpacing[0]) ||
        !std::isfinite(s.pixelSpacing[1]))
      throw std::runtime_error(f + " has a zero or negative PixelSpacing (0028,0030)");
    if (s.ipp.size() != 3)
      throw std::runtime_error(
          f + " has no ImagePositionPatient (0020,0032): slices cannot be ordered");
    if (s.iop.size() != 6)
      throw std::runtime_error(f + " has no ImageOrientationPatient (0020,0037)");
    if (s.rows != first.rows || s.cols != first.cols)
      throw std::runtime_error(
          f + " is " + std::to_string(s.cols) + " x " + std::to_string(s.rows) +
          " pixels, unlike the series' first slice (" + std::to_string(first.cols) + " x " +
          std::to_string(first.rows) + ")");
    for (int a = 0; a < 6; ++a)
      if (std::abs(s.iop[a] - first.iop[a]) > 1e-4)
        throw std::runtime_error(f + " has an orientation different from the other slices");
    for (int a = 0; a < 2; ++a)
      if (std::abs(s.pixelSpacing[a] - first.pixelSpacing[a]) > 1e-6 * first.pixelSpacing[a] + 1e-9)
        throw std::runtime_error(f + " has a pixel spacing different from the other slices");
  }
  if (slices.size() < 2)
    throw std::runtime_error(where + " has a single slice: a volume needs at least two");

  // Slice ordering along the normal = row direction x column direction.
  std::array<double, 3> r{first.iop[0], first.iop[1], first.iop[2]},
      c{first.iop[3], first.iop[4], first.iop[5]};
  std::array<double, 3> n{r[1] * c[2] - r[2] * c[1], r[2] * c[0] - r[0] * c[2],
                          r[0] * c[1] - r[1] * c[0]};
  double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(nn > 0.5))
    throw std::runtime_error(where + " has an invalid ImageOrientationPatient");
  for (auto& v : n)
    v /= nn;
  for (auto& s : slices)
    s.position = s.ipp[0] * n[0] + s.ipp[1] * n[1] + s.ipp[2] * n[2];
  std::sort(slices.begin(), slices.end(),
            [](const SliceHeader& a, const SliceHeader& b) { return a.position < b.position; });
  const size_t ns = slices.size();
  const double meanGap = (slices.back().position - slices.front().position) / double(ns - 1);
  for (size_t i = 0; i + 1 < ns; ++i) {
    double gap = slices[i + 1].position - slices[i].position;
    if (gap < 1e-3)
      throw std::runtime_error(where + ": slices '" + slices[i].file.filename().string() +
                               "' and '" + slices[i + 1].file.filename().string() +
                               "' lie at the same position");
    double tol = std::max(opt.sliceGapToleranceMm, opt.sliceGapToleranceRel * meanGap);
    if (std::abs(gap - meanGap) > tol) {
      std::ostringstream os;
      os << where << " has inconsistent slice spacing: the gap between '"
         << slices[i].file.filename().string() << "' and '"
         << slices[i + 1].file.filename().string() << "' is " << gap << " mm while the mean gap is "
         << meanGap << " mm (a slice may be missing)";
      throw std::runtime_error(os.str());
    }
  }

  const uint64_t bytes = uint64_t(first.rows) * first.cols * ns * sizeof(float);
  CheckMemoryBudget(bytes, opt.maxMemoryBytes,
                    "the CT (" + std::to_string(first.cols) + " x " + std::to_string(first.rows) +
                        " x " + std::to_string(ns) + " voxels)");

  CTImage ct;
  ct.source = dir.string();
  ct.format = "DICOM";
  ct.modality = first.modality;
  ct.seriesUID = first.seriesUID;
  ct.seriesDescription = first.description;
  ct.transferSyntax = first.transferSyntax;
  ct.numFiles = int(ns);
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{size_t(first.cols), size_t(first.rows), ns}});
  ct.hu->SetRegions(region);
  HUImage::SpacingType sp;
  sp[0] = first.pixelSpacing[1]; // PixelSpacing = row spacing \ column spacing
  sp[1] = first.pixelSpacing[0];
  sp[2] = meanGap;
  ct.hu->SetSpacing(sp);
  HUImage::PointType origin;
  for (int a = 0; a < 3; ++a)
    origin[a] = slices.front().ipp[a];
  ct.hu->SetOrigin(origin);
  HUImage::DirectionType dirm;
  for (int a = 0; a < 3; ++a) {
    dirm[a][0] = r[a];
    dirm[a][1] = c[a];
    dirm[a][2] = n[a];
  }
  ct.hu->SetDirection(dirm);
  ct.hu->Allocate();

  using SliceImage = itk::Image<float, 3>;
  const size_t perSlice = size_t(first.cols) * first.rows;
  for (size_t k = 0; k < ns; ++k) {
    progress.Range(0.1, 1.0)(double(k) / ns, "reading DICOM");
    auto io = itk::GDCMImageIO::New();
    auto reader = itk::ImageFileReader<SliceImage>::New();
    reader->SetImageIO(io);
    reader->SetFileName(slices[k].file.string());
    try {
      reader->Update();
    } catch (const itk::ExceptionObject& e) {
      throw std::runtime_error("cannot read the pixels of '" + slices[k].file.string() +
                               "' (truncated or corrupt DICOM file): " + e.GetDescription());
    }
    SliceImage* img = reader->GetOutput();
    auto s = img->GetLargestPossibleRegion().GetSize();
    if (s[0] != size_t(first.cols) || s[1] != size_t(first.rows) || s[2] != 1)
      throw std::runtime_error("'" + slices[k].file.string() + "' decoded to an unexpected size");
    std::copy_n(img->GetBufferPointer(), perSlice, ct.hu->GetBufferPointer() + k * perSlice);
  }
  progress.Range(0.1, 1.0)(1.0, "reading DICOM");
  UpdateHURange(ct);
  return ct;
}

// ---------------------------------------------------------------------------------------------
// Single volume files

/// True when the file's text header names its voxel spacing (NRRD: spacings or space directions;
/// MetaImage: ElementSpacing or ElementSize). ITK silently assumes 1 mm when they are missing.
bool HeaderNamesSpacing(const fs::path& file, const std::string& format) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  int lines = 0;
  while (std::getline(in, line) && lines++ < 200) {
    if (format == "NRRD") {
      if (line.empty() || line == "\r")
        break; // end of the NRRD header
      std::string l = ToLower(line);
      if (l.rfind("spacings:", 0) == 0 || l.rfind("space directions:", 0) == 0)
        return true;
    } else {
      std::string l = ToLower(Trim(line));
      if (l.rfind("elementspacing", 0) == 0 || l.rfind("elementsize", 0) == 0)
        return true;
      if (l.rfind("elementdatafile", 0) == 0)
        break;
    }
  }
  return false;
}

CTImage ReadVolumeFile(const fs::path& file, const ReadOptions& opt, const Progress& progress) {
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
                             "': unknown file type (expected a DICOM folder, .nrrd, .nhdr, .mha, "
                             ".mhd, .nii, .nii.gz or .inv3)");
  }
  if (!io->CanReadFile(file.c_str()))
    throw std::runtime_error("'" + file.string() + "' cannot be read as " + format +
                             " (corrupt or not " + format + ")");
  io->SetFileName(file.string());
  try {
    io->ReadImageInformation();
  } catch (const itk::ExceptionObject& e) {
    throw std::runtime_error("cannot read the header of '" + file.string() +
                             "': " + e.GetDescription());
  }
  if (io->GetNumberOfDimensions() != 3)
    throw std::runtime_error("'" + file.string() + "' is a " +
                             std::to_string(io->GetNumberOfDimensions()) +
                             "-D image; a CT volume must be 3-D");
  if (io->GetNumberOfComponents() != 1)
    throw std::runtime_error("'" + file.string() + "' has " +
                             std::to_string(io->GetNumberOfComponents()) +
                             " components per voxel; a CT has one");
  if ((format == "NRRD" || format == "MetaImage") && !HeaderNamesSpacing(file, format))
    throw std::runtime_error("'" + file.string() +
                             "' does not give its voxel spacing: the size in mm is unknown");
  uint64_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    double s = io->GetSpacing(a);
    if (!(s > 0) || !std::isfinite(s))
      throw std::runtime_error("'" + file.string() +
                               "' has a zero or invalid voxel spacing along axis " +
                               std::to_string(a));
    voxels *= io->GetDimensions(a);
  }
  if (format == "MetaImage") {
    std::string mod;
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
  CTImage ct;
  ct.hu = reader->GetOutput();
  ct.hu->DisconnectPipeline();
  ct.source = file.string();
  ct.format = format;
  ct.numFiles = 1;
  UpdateHURange(ct);
  return ct;
}

} // namespace

std::vector<DicomSeriesInfo> ListDicomSeries(const std::string& folder) {
  return Summaries(ScanFolder(folder, Progress()));
}

CTImage ReadCT(const std::string& path, const ReadOptions& options, const Progress& progress) {
  fs::path p(path);
  if (!fs::exists(p))
    throw std::runtime_error("'" + path + "' does not exist");
  if (fs::is_directory(p))
    return ReadDicomFolder(p, options, progress);
  std::string lower = ToLower(p.filename().string());
  if (lower.size() > 5 && lower.compare(lower.size() - 5, 5, ".inv3") == 0)
    return ReadInvesaliusProject(path, options, progress);
  return ReadVolumeFile(p, options, progress);
}

} // namespace bm
