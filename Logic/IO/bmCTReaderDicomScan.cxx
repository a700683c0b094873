// bmCTReaderDicomScan.cxx - the DICOM series in a folder: every file's header read with GDCM and
// checked, the image files grouped into series (by SeriesInstanceUID, or without one by the
// attributes that tell series apart), and the series to read chosen (bmCTReaderInternal.h).
#include "bmCTReaderInternal.h"

#include "bmDicomFileCheck.h"

#include <gdcmDicts.h>
#include <gdcmExplicitDataElement.h>
#include <gdcmGlobal.h>
#include <gdcmImplicitDataElement.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDs.h>
#include <gdcmStringFilter.h>
#include <gdcmTransferSyntax.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace bm::ctreader {

namespace {

std::string Trim(std::string s) {
  while (!s.empty() && (std::isspace((unsigned char)s.back()) || s.back() == '\0'))
    s.pop_back();
  size_t i = 0;
  while (i < s.size() && std::isspace((unsigned char)s[i]))
    ++i;
  return s.substr(i);
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

} // namespace

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

/// Read the headers of the folder's files. magicOnly: only files with the DICM magic (the folder
/// of a single file given on the command line may hold other files).
ScannedFolder ScanFolder(const fs::path& dir, const Progress& progress, bool magicOnly) {
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

namespace {

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

} // namespace

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

} // namespace bm::ctreader

namespace bm {

std::vector<DicomSeriesInfo> ListDicomSeries(const std::string& folder) {
  return ctreader::Summaries(ctreader::ScanFolder(folder, Progress()));
}

} // namespace bm
