// bmHeaderCheckMeta.cxx - the MetaImage header check (.mha/.mhd): its keys, sizes, type, channels,
// spacing, origin, direction, data file and bytes, a compressed stream inflated to check it
// (bmHeaderCheckInternal.h).
#include "bmHeaderCheckInternal.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

namespace fs = std::filesystem;

namespace bm::headercheck {

namespace {

int MetaTypeBytes(const std::string& t, bool& integer) {
  static const std::map<std::string, int> types = {
      {"MET_CHAR", 1},      {"MET_UCHAR", 1},      {"MET_SHORT", 2}, {"MET_USHORT", 2},
      {"MET_INT", 4},       {"MET_UINT", 4},       {"MET_LONG", 4},  {"MET_ULONG", 4},
      {"MET_LONG_LONG", 8}, {"MET_ULONG_LONG", 8}, {"MET_FLOAT", 4}, {"MET_DOUBLE", 8}};
  auto it = types.find(t);
  if (it == types.end())
    return 0;
  integer = t != "MET_FLOAT" && t != "MET_DOUBLE";
  return it->second;
}

} // namespace

VolumeHeader CheckMeta(const fs::path& file, const HeaderLimits& limits) {
  uint64_t headerBytes = 0;
  auto lines = HeaderLines(file, headerBytes, [](const std::string& l) {
    return Lower(Trim(l)).rfind("elementdatafile", 0) == 0;
  });
  if (!lines.empty() && lines[0].rfind("NRRD", 0) == 0)
    throw std::runtime_error(Q(file) + " is a NRRD file, not a MetaImage: rename it to .nrrd");
  std::map<std::string, std::string> f;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string l = Trim(lines[i]);
    if (l.empty())
      continue;
    size_t eq = l.find('=');
    if (eq == std::string::npos)
      throw std::runtime_error(Q(file) + ": header line " + std::to_string(i + 1) +
                               " is not 'Key = Value' (not a MetaImage header)");
    f[Lower(Trim(l.substr(0, eq)))] = Trim(l.substr(eq + 1));
  }
  if (!f.count("elementdatafile"))
    throw std::runtime_error(Q(file) + ": the MetaImage header has no ElementDataFile");
  VolumeHeader h;
  h.format = "MetaImage";
  const std::string nd = f.count("ndims") ? f["ndims"] : "";
  if (nd != "3")
    throw std::runtime_error(Q(file) + " is a " + (nd.empty() ? "?" : nd) +
                             "-D image (NDims); a CT volume must be 3-D");
  if (!f.count("dimsize"))
    throw std::runtime_error(Q(file) + ": the MetaImage header has no DimSize");
  Sizes(file, "DimSize", f["dimsize"], 3, h.dims);
  const std::string type = Trim(f.count("elementtype") ? f["elementtype"] : "");
  h.componentBytes = MetaTypeBytes(type, h.integerType);
  if (!h.componentBytes)
    throw std::runtime_error(Q(file) + ": unsupported ElementType '" + type + "'");
  const int channels =
      f.count("elementnumberofchannels") ? std::atoi(f["elementnumberofchannels"].c_str()) : 1;
  if (channels < 1 || channels > limits.maxComponents)
    throw std::runtime_error(
        Q(file) + " has " + std::to_string(channels) + " components per voxel; " +
        (limits.maxComponents == 1
             ? std::string("a CT has one")
             : "at most " + std::to_string(limits.maxComponents) + " are accepted"));
  h.components = channels;
  CheckMemory(file, h, limits);
  if (f.count("elementspacing"))
    CheckSpacing(file, Numbers(f["elementspacing"]));
  else if (f.count("elementsize"))
    CheckSpacing(file, Numbers(f["elementsize"]));
  else
    throw std::runtime_error(Q(file) +
                             " does not give its voxel spacing: the size in mm is unknown");
  for (const char* k : {"offset", "origin", "position"})
    if (f.count(k))
      CheckFinite(file, std::string("origin (") + k + ")", Numbers(f[k]), 3);
  for (const char* k : {"transformmatrix", "rotation", "orientation"})
    if (f.count(k)) {
      auto m = Numbers(f[k]);
      CheckFinite(file, std::string("direction (") + k + ")", m, 9);
      for (int a = 0; a < 3; ++a)
        if (!(std::abs(m[size_t(3 * a)]) + std::abs(m[size_t(3 * a + 1)]) +
                  std::abs(m[size_t(3 * a + 2)]) >
              1e-3)) // a direction cosine axis has length 1
          throw std::runtime_error(Q(file) + ": direction axis " + std::to_string(a) +
                                   " is zero (or nearly: its entries sum to at most 0.001)");
    }
  const std::string dataName = f["elementdatafile"];
  const bool local = Lower(dataName) == "local";
  h.dataFile = local ? file : DataFileBeside(file, dataName, limits);
  const bool compressed = Lower(f.count("compresseddata") ? f["compresseddata"] : "") == "true";
  const uint64_t need =
      h.dims[0] * h.dims[1] * h.dims[2] * uint64_t(h.componentBytes) * uint64_t(h.components);
  long long skip = f.count("headersize") ? std::atoll(f["headersize"].c_str()) : 0;
  const uint64_t offset = local ? headerBytes : uint64_t(std::max(0LL, skip));
  if (!compressed && skip >= 0) {
    CheckDataBytes(file, h.dataFile, offset, need, false);
  } else if (compressed) {
    // ITK's MetaImage reader inflates exactly CompressedDataSize bytes and hands on whatever came
    // out (a stream cut in half reads as half a CT, the rest zero): inflate it here first.
    if (!f.count("compresseddatasize"))
      throw std::runtime_error(Q(file) +
                               " is compressed but does not give CompressedDataSize: ITK's "
                               "MetaImage reader cannot decode it (it reads zeros); write it "
                               "with CompressedDataSize, or uncompressed");
    const std::string csText = f["compresseddatasize"];
    char* end = nullptr;
    const double cs = std::strtod(csText.c_str(), &end);
    const uint64_t size = fs::file_size(h.dataFile);
    const uint64_t have = size > offset ? size - offset : 0;
    // Digits only: ITK reads the field as an integer ("1e3" would be 1 byte to it).
    if (end == csText.c_str() || *end != '\0' || !(cs >= 1) || cs != std::floor(cs) ||
        csText.find_first_not_of("0123456789") != std::string::npos)
      throw std::runtime_error(Q(file) + ": CompressedDataSize '" + csText +
                               "' is not a whole number of bytes");
    if (cs > double(have))
      throw std::runtime_error(Q(file) + " is truncated: CompressedDataSize is " + csText +
                               " bytes, the file holds " + std::to_string(have));
    bool complete = false;
    const uint64_t out = ZlibBytes(file, h.dataFile, offset, uint64_t(cs), need, complete);
    if (out < need)
      throw std::runtime_error(Q(file) + " is truncated: its voxels need " + std::to_string(need) +
                               " bytes, its compressed data (" + csText + " bytes) inflate to " +
                               std::to_string(out) +
                               (complete ? "" : " before they end mid-stream"));
  }
  return h;
}

} // namespace bm::headercheck
