#include "bmCTReader.h"
#include "bmCTFileTypes.h"

#include "bmDicomFileCheck.h"
#include "bmHeaderCheck.h"
#include "bmInvesaliusReader.h"
#include "bmTiltedStack.h"

#include <gdcmDicts.h>
#include <gdcmExplicitDataElement.h>
#include <gdcmGlobal.h>
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
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace bm {

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

double Dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Largest deviation of a direction cosine's length from 1, and of the dot product of two
/// directions from 0 (GDCM's own tolerance for ImageOrientationPatient).
constexpr double kOrientationTolerance = 1e-3;
/// Largest angle between the slice positions' line and the slice normal (gantry tilts reach 30).
constexpr double kMaxTiltDeg = 45;

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
  std::string seriesNumber, studyUID, rescaleType, sopClassUID;
  std::vector<double> rescaleSlope, rescaleIntercept; // empty when absent
  int bitsAllocated = 0;
  std::string seriesId; // seriesUID, or a "noUID-..." id from other attributes
  int rows = 0, cols = 0;
  std::vector<double> pixelSpacing, ipp, iop;
  bool hasPixelData = false;
  double position = 0; // along the slice normal, mm
};

/// Id of a series without SeriesInstanceUID, from the attributes that tell series apart:
/// "noUID-<SeriesNumber>-<Modality>-<cols>x<rows>-<8 hex digits of FNV-1a(study UID,
/// orientation)>".
std::string FallbackSeriesId(const SliceHeader& h) {
  std::ostringstream key;
  key << h.studyUID << "|";
  for (double v : h.iop)
    key << std::lround(v * 1000) << ",";
  uint32_t hash = 2166136261u;
  for (unsigned char c : key.str())
    hash = (hash ^ c) * 16777619u;
  char hex[9];
  std::snprintf(hex, sizeof hex, "%08x", hash);
  std::string number;
  for (char c : h.seriesNumber)
    if (std::isalnum((unsigned char)c))
      number.push_back(c);
  std::string modality;
  for (char c : h.modality)
    if (std::isalnum((unsigned char)c))
      modality.push_back(c);
  return "noUID-" + (number.empty() ? std::string("x") : number) + "-" +
         (modality.empty() ? std::string("x") : modality) + "-" + std::to_string(h.cols) + "x" +
         std::to_string(h.rows) + "-" + hex;
}

SliceHeader ReadSliceHeader(const fs::path& file) {
  const DicomFileSummary check = CheckDicomElements(file);
  if (!check.hasPixelData) {
    SliceHeader none;
    none.file = file; // a complete DICOM file without pixel data: not an image (or cut short)
    none.seriesUID = check.seriesUID;
    none.sopClassUID = check.sopClassUID;
    return none;
  }
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
  h.sopClassUID = str(0x0008, 0x0016);
  h.description = str(0x0008, 0x103e);
  h.frames = str(0x0028, 0x0008);
  h.seriesNumber = str(0x0020, 0x0011);
  h.studyUID = str(0x0020, 0x000d);
  h.rescaleType = str(0x0028, 0x1054);
  h.rescaleSlope = ParseNumbers(str(0x0028, 0x1053));
  h.rescaleIntercept = ParseNumbers(str(0x0028, 0x1052));
  {
    std::string bits = str(0x0028, 0x0100);
    h.bitsAllocated = bits.empty() ? 0 : std::atoi(bits.c_str());
  }
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
  // The data set reaches its pixel data: an image, which needs rows and columns.
  if (h.rows <= 0 || h.cols <= 0)
    throw std::runtime_error("'" + file.string() +
                             "' holds pixel data but no valid Rows (0028,0010) and Columns "
                             "(0028,0011): a damaged image");
  h.hasPixelData = true;
  h.seriesId = h.seriesUID.empty() ? FallbackSeriesId(h) : h.seriesUID;
  return h;
}

/// "skipped N files that are not DICOM: a, b, c" (at most 5 named).
std::string SkippedText(const std::vector<std::string>& names) {
  std::string s = "skipped " + std::to_string(names.size()) + " file" +
                  (names.size() == 1 ? "" : "s") + " that " + (names.size() == 1 ? "is" : "are") +
                  " not DICOM: ";
  for (size_t i = 0; i < names.size() && i < 5; ++i)
    s += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 5)
    s += ", ...";
  return s;
}

struct ScannedFolder {
  std::map<std::string, std::vector<SliceHeader>> series; // by series id
  std::vector<SliceHeader> withoutImage;                  // DICOM files that end without pixel data
  std::vector<std::string> notDicom;                      // names of files skipped as not DICOM
};

/// Read the headers of the folder's files. magicOnly: only files with the DICM magic (the folder
/// of a single file given on the command line may hold other files).
ScannedFolder ScanFolder(const fs::path& dir, const Progress& progress, bool magicOnly = false) {
  if (!fs::exists(dir))
    throw std::runtime_error("'" + dir.string() + "' does not exist");
  if (!fs::is_directory(dir))
    throw std::runtime_error("'" + dir.string() + "' is not a folder");
  std::vector<fs::path> files;
  ScannedFolder out;
  for (const auto& e : fs::directory_iterator(dir)) {
    // FIFOs, devices, sockets and folders are not files to read.
    if (!e.is_regular_file() || IgnorableFile(e.path()) || (magicOnly && !HasDicomMagic(e.path())))
      continue;
    if (!MayBeDicom(e.path()))
      out.notDicom.push_back(e.path().filename().string()); // a README, a picture: said, skipped
    else
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::sort(out.notDicom.begin(), out.notDicom.end());
  if (files.empty())
    throw std::runtime_error("folder '" + dir.string() + "' holds no DICOM files to read" +
                             (out.notDicom.empty() ? std::string(" (it is empty)")
                                                   : " (" + SkippedText(out.notDicom) + ")"));
  for (size_t i = 0; i < files.size(); ++i) {
    if (i % 16 == 0)
      progress(double(i) / files.size(), "scanning DICOM headers");
    SliceHeader h = ReadSliceHeader(files[i]);
    if (!h.hasPixelData) {
      out.withoutImage.push_back(std::move(h)); // presentation states, reports, ...: not images
      continue;
    }
    out.series[h.seriesId].push_back(std::move(h));
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
       << " slices of " << s.cols << " x " << s.rows << " pixels"
       << (s.seriesNumber.empty() ? "" : ", series number " + s.seriesNumber)
       << (s.description.empty() ? "" : ", \"" + s.description + "\"")
       << (s.hasUID ? "" : " (no SeriesInstanceUID)");
  return os.str();
}

std::vector<DicomSeriesInfo> Summaries(const ScannedFolder& sf) {
  std::vector<DicomSeriesInfo> v;
  for (const auto& [id, slices] : sf.series) {
    const SliceHeader& f = slices.front();
    v.push_back({id, f.modality, f.description, int(slices.size()), f.rows, f.cols, f.seriesNumber,
                 !f.seriesUID.empty()});
  }
  return v;
}

struct ReadOutcome {
  CTImage ct;
  IntensityEvidence evidence;
};

ReadOutcome ReadDicomSeries(const fs::path& dir, std::vector<SliceHeader>& slices,
                            const ReadOptions& opt, const Progress& progress);

/// Choose the series to read from a scanned folder (opt.seriesUID, or the only one).
std::vector<SliceHeader>& ChooseSeries(ScannedFolder& scanned, const fs::path& dir,
                                       const ReadOptions& opt) {
  if (!opt.seriesUID.empty()) {
    auto it = scanned.series.find(opt.seriesUID);
    if (it == scanned.series.end())
      throw std::runtime_error("series " + opt.seriesUID + " is not in '" + dir.string() +
                               "'; the folder holds:" + DescribeSeries(Summaries(scanned)));
    return it->second;
  }
  if (scanned.series.size() > 1)
    throw std::runtime_error("folder '" + dir.string() + "' holds " +
                             std::to_string(scanned.series.size()) +
                             " DICOM series; choose one by the id listed (--series ID):" +
                             DescribeSeries(Summaries(scanned)));
  return scanned.series.begin()->second;
}

/// A file of the chosen series that ends without its image (cut short at an element's end) is a
/// damaged slice, not a file to leave out: refused by name.
void CheckNoSliceWithoutImage(const ScannedFolder& scanned, const std::vector<SliceHeader>& slices,
                              const fs::path& dir) {
  const SliceHeader& first = slices.front();
  if (first.seriesUID.empty())
    return;
  for (const auto& f : scanned.withoutImage)
    if (f.seriesUID == first.seriesUID &&
        (f.sopClassUID.empty() || f.sopClassUID == first.sopClassUID))
      throw std::runtime_error("'" + f.file.filename().string() + "' in '" + dir.string() +
                               "' belongs to series " + first.seriesId +
                               " but ends without its image (no pixel data): the slice is "
                               "truncated or damaged");
}

ReadOutcome ReadDicomFolder(const fs::path& dir, const ReadOptions& opt, const Progress& progress) {
  ScannedFolder scanned = ScanFolder(dir, progress.Range(0, 0.1));
  std::vector<SliceHeader>& slices = ChooseSeries(scanned, dir, opt);
  CheckNoSliceWithoutImage(scanned, slices, dir);
  ReadOutcome r = ReadDicomSeries(dir, slices, opt, progress.Range(0.1, 1));
  if (!scanned.notDicom.empty())
    r.ct.notes.push_back(SkippedText(scanned.notDicom) + " (in '" + dir.string() + "')");
  return r;
}

/// A single DICOM file: the series it belongs to in its folder.
ReadOutcome ReadDicomFile(const fs::path& file, const ReadOptions& opt, const Progress& progress) {
  SliceHeader h = ReadSliceHeader(file);
  if (!h.hasPixelData)
    throw std::runtime_error("'" + file.string() + "' is a DICOM file without an image");
  if (!h.frames.empty() && std::atoi(h.frames.c_str()) > 1)
    throw std::runtime_error("'" + file.string() + "' is a multi-frame DICOM image (" + h.frames +
                             " frames); only series of single-frame slices are supported");
  const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  ScannedFolder scanned = ScanFolder(dir, progress.Range(0, 0.1), true);
  auto it = scanned.series.find(h.seriesId);
  if (it == scanned.series.end())
    throw std::runtime_error("'" + file.string() + "': its series was not found in its folder");
  if (!opt.seriesUID.empty() && opt.seriesUID != h.seriesId)
    throw std::runtime_error("'" + file.string() + "' belongs to series " + h.seriesId + ", not " +
                             opt.seriesUID);
  CheckNoSliceWithoutImage(scanned, it->second, dir);
  ReadOutcome r = ReadDicomSeries(dir, it->second, opt, progress.Range(0.1, 1));
  r.ct.notes.push_back("'" + file.filename().string() + "' is one slice of series " + h.seriesId +
                       ": its " + std::to_string(r.ct.numFiles) + " slices in '" + dir.string() +
                       "' were read");
  return r;
}

ReadOutcome ReadDicomSeries(const fs::path& dir, std::vector<SliceHeader>& slices,
                            const ReadOptions& opt, const Progress& progress) {
  const SliceHeader& first = slices.front();
  const std::string where = "DICOM series " + first.seriesId + " in '" + dir.string() + "'";

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
    if (!std::all_of(s.ipp.begin(), s.ipp.end(), [](double v) { return std::isfinite(v); }))
      throw std::runtime_error(f + " has a non-finite ImagePositionPatient (0020,0032)");
    if (s.iop.size() != 6)
      throw std::runtime_error(f + " has no ImageOrientationPatient (0020,0037)");
    if (!std::all_of(s.iop.begin(), s.iop.end(), [](double v) { return std::isfinite(v); }))
      throw std::runtime_error(f + " has a non-finite ImageOrientationPatient (0020,0037)");
    if (s.modality != first.modality)
      throw std::runtime_error(f + " has modality '" + s.modality +
                               "', unlike the series' first "
                               "slice ('" +
                               first.modality + "')");
    for (const auto* v : {&s.rescaleSlope, &s.rescaleIntercept})
      if (!v->empty() && (v->size() != 1 || !std::isfinite(v->front())))
        throw std::runtime_error(
            f + " has an invalid or non-finite Rescale" +
            (v == &s.rescaleSlope ? "Slope (0028,1053)" : "Intercept (0028,1052)"));
    if (!s.rescaleSlope.empty() && s.rescaleSlope.front() == 0)
      throw std::runtime_error(f + " has a RescaleSlope (0028,1053) of 0");
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

  // Orientation: the row and column directions must be unit vectors at right angles (GDCM's
  // tolerance, 0.001); a skewed or scaled pair would shrink or shear the volume.
  std::array<double, 3> r{first.iop[0], first.iop[1], first.iop[2]},
      c{first.iop[3], first.iop[4], first.iop[5]};
  {
    const std::string f = "'" + first.file.filename().string() + "' of " + where;
    const double lr = std::sqrt(Dot(r, r)), lc = std::sqrt(Dot(c, c)), rc = Dot(r, c);
    for (const auto& [len, which] : {std::pair{lr, "row"}, std::pair{lc, "column"}})
      if (std::abs(len - 1) > kOrientationTolerance) {
        std::ostringstream os;
        os << f << ": the " << which << " direction of its ImageOrientationPatient (0020,0037) has "
           << "length " << len << ", not 1 (direction cosines are unit vectors)";
        throw std::runtime_error(os.str());
      }
    if (std::abs(rc) > kOrientationTolerance) {
      std::ostringstream os;
      os << f << ": the row and column directions of its ImageOrientationPatient (0020,0037) are "
         << std::acos(std::clamp(rc / (lr * lc), -1.0, 1.0)) * 180 / M_PI
         << " deg apart, not 90 (row . column = " << rc << ")";
      throw std::runtime_error(os.str());
    }
    // Within the tolerance: make them exactly orthonormal for the image's direction matrix.
    for (auto& v : r)
      v /= lr;
    const double rc1 = Dot(r, c);
    for (int a = 0; a < 3; ++a)
      c[size_t(a)] -= rc1 * r[size_t(a)];
    const double lc1 = std::sqrt(Dot(c, c));
    for (auto& v : c)
      v /= lc1;
  }
  // Slice ordering along the normal = row direction x column direction.
  std::array<double, 3> n{r[1] * c[2] - r[2] * c[1], r[2] * c[0] - r[0] * c[2],
                          r[0] * c[1] - r[1] * c[0]};
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
  // The positions must step uniformly (along a line): along the normal, or, with gantry tilt or
  // sheared positions, along a line at an angle to it (resampled after reading, bmTiltedStack.h).
  std::array<double, 3> step;
  for (int a = 0; a < 3; ++a)
    step[size_t(a)] =
        (slices.back().ipp[size_t(a)] - slices.front().ipp[size_t(a)]) / double(ns - 1);
  const double stepLen = std::sqrt(Dot(step, step));
  for (size_t k = 1; k + 1 < ns; ++k) {
    double off = 0;
    for (int a = 0; a < 3; ++a) {
      const double e =
          slices[k].ipp[size_t(a)] - slices.front().ipp[size_t(a)] - double(k) * step[size_t(a)];
      off += e * e;
    }
    off = std::sqrt(off);
    if (off > std::max(opt.sliceGapToleranceMm, opt.sliceGapToleranceRel * stepLen)) {
      std::ostringstream os;
      os << "'" << slices[k].file.filename().string() << "' of " << where << " lies " << off
         << " mm off the line through the other slices' positions (ImagePositionPatient): slice "
            "positions must step uniformly";
      throw std::runtime_error(os.str());
    }
  }
  // Gantry tilt or shear: the step's part in the slice plane, over the whole stack.
  const double inPlaneStep = std::sqrt(std::max(0.0, stepLen * stepLen - meanGap * meanGap));
  const double tiltDeg = std::atan2(inPlaneStep, meanGap) * 180 / M_PI;
  const bool tilted =
      inPlaneStep * double(ns - 1) > 0.1 * std::min(first.pixelSpacing[0], first.pixelSpacing[1]);
  if (tilted && tiltDeg > kMaxTiltDeg) {
    std::ostringstream os;
    os << where << ": its slice positions move " << tiltDeg
       << " deg away from the slice normal, more than the " << kMaxTiltDeg
       << " deg a gantry tilt reaches (ImagePositionPatient or ImageOrientationPatient is wrong)";
    throw std::runtime_error(os.str());
  }

  const uint64_t bytes =
      uint64_t(first.rows) * first.cols * ns * (sizeof(float) + opt.extraBytesPerVoxel);
  CheckMemoryBudget(bytes, opt.maxMemoryBytes,
                    "the CT (" + std::to_string(first.cols) + " x " + std::to_string(first.rows) +
                        " x " + std::to_string(ns) + " voxels" +
                        (opt.extraBytesPerVoxel ? ", with the import's working memory" : "") + ")");

  ReadOutcome out;
  CTImage& ct = out.ct;
  ct.source = dir.string();
  ct.format = "DICOM";
  ct.modality = first.modality;
  ct.seriesUID = first.seriesId;
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
  sp[2] = tilted ? stepLen : meanGap; // tilted: one slice position to the next
  ct.hu->SetSpacing(sp);
  HUImage::PointType origin;
  for (int a = 0; a < 3; ++a)
    origin[a] = slices.front().ipp[a];
  ct.hu->SetOrigin(origin);
  HUImage::DirectionType dirm;
  for (int a = 0; a < 3; ++a) {
    dirm[a][0] = r[a];
    dirm[a][1] = c[a];
    dirm[a][2] = tilted ? step[size_t(a)] / stepLen : n[a];
  }
  ct.hu->SetDirection(dirm);
  ct.hu->Allocate();

  using SliceImage = itk::Image<float, 3>;
  const size_t perSlice = size_t(first.cols) * first.rows;
  for (size_t k = 0; k < ns; ++k) {
    progress(double(k) / ns, "reading DICOM");
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
  progress(1.0, "reading DICOM");
  if (tilted) {
    std::ostringstream os;
    os.precision(3);
    os << "the slice positions move " << tiltDeg
       << " deg off the slice normal (gantry tilt or sheared positions): the slices were "
          "resampled onto a grid along the normal, "
       << meanGap << " mm apart (linear interpolation, every voxel at its place)";
    ct.notes.push_back(os.str());
  }
  if (first.seriesUID.empty())
    ct.notes.push_back("the series has no SeriesInstanceUID (0020,000E): its " +
                       std::to_string(ns) +
                       " slices were grouped by SeriesNumber, "
                       "ImageOrientationPatient, Rows/Columns, StudyInstanceUID and Modality as "
                       "series " +
                       first.seriesId);
  IntensityEvidence& ev = out.evidence;
  ev.modality = first.modality;
  ev.hasRescale = !first.rescaleSlope.empty() || !first.rescaleIntercept.empty();
  ev.rescaleType = first.rescaleType;
  ev.storedBits = first.bitsAllocated;
  ev.storedInteger = true;
  return out;
}

// ---------------------------------------------------------------------------------------------
// Single volume files

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

/// A single file that is DICOM: the DICM magic, or a DICOM extension.
bool LooksLikeDicomFile(const fs::path& file) {
  std::string ext = ToLower(file.extension().string());
  return HasDicomMagic(file) || ext == ".dcm" || ext == ".dicom";
}

CTImage ReadCTUnguarded(const std::string& path, const ReadOptions& options,
                        const Progress& progress) {
  fs::path p(path);
  if (!fs::exists(p))
    throw std::runtime_error("'" + path + "' does not exist");
  ReadOutcome r;
  const Progress reading = progress.Range(0, 0.95);
  if (fs::is_directory(p)) {
    r = ReadDicomFolder(p, options, reading);
  } else {
    CheckRegularFile(p, "the input");
    std::string lower = ToLower(p.filename().string());
    if (lower.size() > 5 && lower.compare(lower.size() - 5, 5, ".inv3") == 0) {
      r.ct = ReadInvesaliusProject(path, options, reading);
      r.evidence.modality = r.ct.modality;
    } else if (LooksLikeDicomFile(p)) {
      r = ReadDicomFile(p, options, reading);
    } else {
      r = ReadVolumeFile(p, options, reading);
    }
  }
  CTImage& ct = r.ct;
  r.evidence.file = path;
  r.evidence.format = ct.format;
  ApplyIntensityDecision(ct, r.evidence, options.intensity);
  // A tilted DICOM stack (sheared grid): onto a grid along the slice normal, after the values were
  // judged as read (interpolation makes whole numbers fractional), air outside the stack.
  if (StackTiltDeg(ct.hu) > 1e-6) {
    ct.hu = ResampleTiltedStack(ct.hu, ct.huMin, options.maxMemoryBytes, progress.Range(0.95, 1));
    UpdateHURange(ct);
  }
  progress(1.0, "checking the values");
  return ct;
}

} // namespace

void ApplyIntensityDecision(CTImage& ct, IntensityEvidence ev, const IntensityOptions& options) {
  // Value range, and whether every value is whole.
  {
    const float* v = ct.hu->GetBufferPointer();
    const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    bool whole = true;
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(v[i]))
        throw std::runtime_error("'" + ev.file +
                                 "' holds a non-finite voxel value (NaN or infinite)");
      lo = std::min(lo, v[i]);
      hi = std::max(hi, v[i]);
      whole = whole && v[i] == std::nearbyint(v[i]);
    }
    ev.minValue = lo;
    ev.maxValue = hi;
    ev.allIntegers = whole;
  }
  ct.intensity = DecideIntensity(ev, options, ct.warnings);
  if (ct.intensity.kind == IntensityKind::GivenMapping) {
    float* v = ct.hu->GetBufferPointer();
    const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
    const double a = ct.intensity.slope, b = ct.intensity.intercept;
    for (size_t i = 0; i < n; ++i)
      v[i] = float(a * double(v[i]) + b);
  }
  UpdateHURange(ct);
}

std::vector<DicomSeriesInfo> ListDicomSeries(const std::string& folder) {
  return Summaries(ScanFolder(folder, Progress()));
}

CTImage ReadCT(const std::string& path, const ReadOptions& options, const Progress& progress) {
  // The boundary: every library failure becomes a message naming the input.
  try {
    return ReadCTUnguarded(path, options, progress);
  } catch (const Cancelled&) {
    throw;
  } catch (const itk::ExceptionObject& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.GetDescription());
  } catch (const std::bad_alloc&) {
    throw std::runtime_error("not enough memory to read '" + path +
                             "' (lower --max-memory's demand by cropping the CT, or free memory)");
  } catch (const std::filesystem::filesystem_error& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.what());
  } catch (const std::runtime_error&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read '" + path + "': " + e.what());
  }
}

} // namespace bm
