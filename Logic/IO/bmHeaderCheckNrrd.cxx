// bmHeaderCheckNrrd.cxx - the NRRD header check (.nrrd/.nhdr): its fields, sizes, type, spacing
// or space directions, origin, data file and bytes (bmHeaderCheckInternal.h).
#include "bmHeaderCheckInternal.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace bm::headercheck {

namespace {

int NrrdTypeBytes(const std::string& t, bool& integer) {
  static const std::map<std::string, int> types = {{"signed char", 1},
                                                   {"int8", 1},
                                                   {"int8_t", 1},
                                                   {"uchar", 1},
                                                   {"unsigned char", 1},
                                                   {"uint8", 1},
                                                   {"uint8_t", 1},
                                                   {"short", 2},
                                                   {"short int", 2},
                                                   {"signed short", 2},
                                                   {"signed short int", 2},
                                                   {"int16", 2},
                                                   {"int16_t", 2},
                                                   {"ushort", 2},
                                                   {"unsigned short", 2},
                                                   {"unsigned short int", 2},
                                                   {"uint16", 2},
                                                   {"uint16_t", 2},
                                                   {"int", 4},
                                                   {"signed int", 4},
                                                   {"int32", 4},
                                                   {"int32_t", 4},
                                                   {"uint", 4},
                                                   {"unsigned int", 4},
                                                   {"uint32", 4},
                                                   {"uint32_t", 4},
                                                   {"longlong", 8},
                                                   {"long long", 8},
                                                   {"long long int", 8},
                                                   {"signed long long", 8},
                                                   {"signed long long int", 8},
                                                   {"int64", 8},
                                                   {"int64_t", 8},
                                                   {"ulonglong", 8},
                                                   {"unsigned long long", 8},
                                                   {"unsigned long long int", 8},
                                                   {"uint64", 8},
                                                   {"uint64_t", 8},
                                                   {"float", 4},
                                                   {"double", 8}};
  auto it = types.find(t);
  if (it == types.end())
    return 0;
  integer = t != "float" && t != "double";
  return it->second;
}

} // namespace

VolumeHeader CheckNrrd(const fs::path& file, const HeaderLimits& limits) {
  uint64_t headerBytes = 0;
  auto lines = HeaderLines(file, headerBytes, [](const std::string& l) { return l.empty(); });
  if (lines.empty() || lines[0].rfind("NRRD000", 0) != 0)
    throw std::runtime_error(Q(file) + " is not a NRRD file (it does not start with NRRD000x)");
  std::map<std::string, std::string> f;
  for (size_t i = 1; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l.empty() || l[0] == '#' || l.find(":=") != std::string::npos)
      continue;
    size_t colon = l.find(": ");
    if (colon == std::string::npos)
      throw std::runtime_error(Q(file) + ": header line " + std::to_string(i + 1) +
                               " is not 'field: value'");
    f[Lower(Trim(l.substr(0, colon)))] = Trim(l.substr(colon + 2));
  }
  VolumeHeader h;
  h.format = "NRRD";
  if (!f.count("dimension") || !f.count("sizes") || !f.count("type"))
    throw std::runtime_error(Q(file) + ": the NRRD header lacks dimension, sizes or type");
  const std::string dim = f["dimension"];
  std::string sizes = f["sizes"];
  if (dim == "4" && limits.maxComponents > 1) {
    // A vector image (a saved voxmap): its first axis holds the values of one voxel.
    std::vector<std::string> words;
    const std::vector<double> n = Numbers(sizes, &words);
    if (words.empty() && n.size() == 4 && n[0] >= 1 && n[0] <= limits.maxComponents &&
        n[0] == std::floor(n[0])) {
      h.components = int(n[0]);
      std::istringstream rest(sizes);
      std::string first;
      rest >> first;
      std::getline(rest, sizes);
    } else {
      throw std::runtime_error(Q(file) + ": a 4-D image must hold 1 to " +
                               std::to_string(limits.maxComponents) +
                               " values per voxel along its first axis, not sizes '" + sizes + "'");
    }
  }
  if (dim != "3" && h.components == 1) {
    uint64_t d4[4] = {1, 1, 1, 1};
    if (dim == "4") {
      uint64_t dims[3];
      std::vector<double> n = Numbers(f["sizes"]);
      Sizes(file, "sizes", f["sizes"], 4, dims);
      d4[3] = uint64_t(n[3]);
    }
    throw std::runtime_error(
        Q(file) + " is a " + dim + "-D image; a CT volume must be 3-D (one value per voxel)" +
        (d4[3] > 1 ? " (its 4th axis has " + std::to_string(d4[3]) + " samples)" : std::string()));
  }
  Sizes(file, "sizes", sizes, 3, h.dims);
  h.componentBytes = NrrdTypeBytes(Lower(f["type"]), h.integerType);
  if (!h.componentBytes)
    throw std::runtime_error(Q(file) + ": unsupported NRRD type '" + f["type"] + "'");
  CheckMemory(file, h, limits);
  if (f.count("spacings")) {
    std::vector<double> spacings = Numbers(f["spacings"]);
    if (h.components > 1 && !spacings.empty())
      spacings.erase(spacings.begin()); // the value axis has none ("nan")
    CheckSpacing(file, spacings);
  } else if (f.count("space directions")) {
    std::string directions = f["space directions"];
    if (h.components > 1 && Lower(directions).rfind("none", 0) == 0)
      directions = directions.substr(4); // the value axis is not a space direction
    std::vector<std::string> words;
    std::vector<double> d = Numbers(directions, &words);
    if (!words.empty() || d.size() != 9)
      throw std::runtime_error(Q(file) + ": 'space directions' must give three 3-vectors, not '" +
                               directions + "'");
    CheckFinite(file, "space direction", d, 9);
    for (int a = 0; a < 3; ++a) {
      double len = std::sqrt(d[3 * a] * d[3 * a] + d[3 * a + 1] * d[3 * a + 1] +
                             d[3 * a + 2] * d[3 * a + 2]);
      if (!(len >= kMinSpacingMm) || len > 1e4) {
        std::ostringstream m;
        m << Q(file) << ": space direction " << a << " has length " << len
          << " mm (the voxel spacing): it must be at least " << kMinSpacingMm
          << " mm and at most 10 000";
        throw std::runtime_error(m.str());
      }
    }
  } else {
    throw std::runtime_error(Q(file) +
                             " does not give its voxel spacing: the size in mm is unknown");
  }
  if (f.count("space origin"))
    CheckFinite(file, "space origin", Numbers(f["space origin"]), 3);
  if (f.count("axis mins"))
    CheckFinite(file, "axis mins", Numbers(f["axis mins"]), 3);
  std::string enc = Lower(f.count("encoding") ? f["encoding"] : "");
  std::string dataName = f.count("data file")  ? f["data file"]
                         : f.count("datafile") ? f["datafile"]
                                               : "";
  h.dataFile = dataName.empty() ? file : DataFileBeside(file, dataName, limits);
  const uint64_t need =
      h.dims[0] * h.dims[1] * h.dims[2] * uint64_t(h.componentBytes) * uint64_t(h.components);
  long long byteSkip = 0;
  if (f.count("byte skip"))
    byteSkip = std::atoll(f["byte skip"].c_str());
  const bool lineSkip = f.count("line skip") && std::atoll(f["line skip"].c_str()) != 0;
  const uint64_t offset = dataName.empty() ? headerBytes : uint64_t(std::max(0LL, byteSkip));
  if (enc == "raw" && byteSkip >= 0 && !lineSkip)
    CheckDataBytes(file, h.dataFile, offset, need, false);
  else if ((enc == "gzip" || enc == "gz") && byteSkip == 0 && !lineSkip)
    CheckDataBytes(file, h.dataFile, offset, need, true);
  return h;
}

} // namespace bm::headercheck
