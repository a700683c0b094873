#include "bmHeaderCheck.h"

#include "bmCTReader.h" // CheckMemoryBudget
#include "bmDicomFileCheck.h"
#include "bmInputFiles.h"
#include "bmRegularFile.h"

#include <zlib.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fs = std::filesystem;

namespace bm {

namespace {

std::string Q(const fs::path& p) {
  // Appended piece by piece: GCC 12 reports a false -Wrestrict for "'" + std::string&&.
  std::string q = "'";
  q += p.string();
  q += '\'';
  return q;
}

std::string Lower(std::string s) {
  for (auto& c : s)
    c = char(std::tolower((unsigned char)c));
  return s;
}

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace((unsigned char)s[a]))
    ++a;
  while (b > a && (std::isspace((unsigned char)s[b - 1]) || s[b - 1] == '\0'))
    --b;
  return s.substr(a, b - a);
}

/// Numbers in `s` separated by blanks, commas or parentheses ("nan" and "inf" parse, as non-finite
/// values the callers refuse). Words such as "none" are returned in `words`.
std::vector<double> Numbers(const std::string& s, std::vector<std::string>* words = nullptr) {
  std::string t = s;
  for (auto& c : t)
    if (c == '(' || c == ')' || c == ',')
      c = ' ';
  std::istringstream is(t);
  std::vector<double> v;
  std::string tok;
  while (is >> tok) {
    char* end = nullptr;
    double x = std::strtod(tok.c_str(), &end);
    if (end && *end == '\0' && end != tok.c_str())
      v.push_back(x);
    else if (words)
      words->push_back(tok);
    else
      v.push_back(std::nan(""));
  }
  return v;
}

void Sizes(const fs::path& file, const std::string& field, const std::string& value, int count,
           uint64_t dims[3]) {
  std::vector<std::string> words;
  std::vector<double> n = Numbers(value, &words);
  if (!words.empty() || int(n.size()) != count)
    throw std::runtime_error(Q(file) + ": '" + field + "' must give " + std::to_string(count) +
                             " whole numbers, not '" + value + "'");
  for (int a = 0; a < count; ++a) {
    if (!(n[size_t(a)] >= 1) || n[size_t(a)] != std::floor(n[size_t(a)]) || n[size_t(a)] > 1e9)
      throw std::runtime_error(Q(file) + ": size " + value + " along axis " + std::to_string(a) +
                               " is not a whole number 1 .. 10^9");
    if (a < 3)
      dims[a] = uint64_t(n[size_t(a)]);
  }
}

void CheckFinite(const fs::path& file, const std::string& what, const std::vector<double>& v,
                 size_t count) {
  if (v.size() < count)
    throw std::runtime_error(Q(file) + ": " + what + " needs " + std::to_string(count) +
                             " numbers");
  for (double x : v)
    if (!std::isfinite(x))
      throw std::runtime_error(Q(file) + " has a non-finite " + what + " (NaN or infinite)");
}

// Smallest voxel spacing accepted (mm): 0.1 um, far below any scanner's; a denormal spacing makes
// the image's direction-times-spacing matrix singular for ITK.
constexpr double kMinSpacingMm = 1e-4;

void CheckSpacing(const fs::path& file, const std::vector<double>& s) {
  CheckFinite(file, "voxel spacing", s, 3);
  for (size_t a = 0; a < 3; ++a)
    if (!(s[a] >= kMinSpacingMm) || s[a] > 1e4) {
      std::ostringstream m;
      m << Q(file) << " has a voxel spacing of " << s[a] << " mm along axis " << a
        << ": it must be at least " << kMinSpacingMm << " mm and at most 10 000 mm";
      throw std::runtime_error(m.str());
    }
}

/// Resolve a detached data file named in a header, refusing paths that leave the header's folder.
fs::path DataFileBeside(const fs::path& header, const std::string& name,
                        const HeaderLimits& limits) {
  if (name.empty())
    throw std::runtime_error(Q(header) + " names an empty data file");
  if (name.find('%') != std::string::npos || name.rfind("LIST", 0) == 0)
    throw std::runtime_error(Q(header) + " names its data as a list or pattern of files ('" + name +
                             "'); only a single data file is supported");
  fs::path p(name);
  const fs::path folder = header.parent_path().empty() ? fs::path(".") : header.parent_path();
  if (!limits.allowDataOutsideFolder) {
    if (p.is_absolute())
      throw std::runtime_error(Q(header) + " names its data file by an absolute path ('" + name +
                               "'); data files must lie beside the header (allow other places "
                               "with --allow-outside-data)");
    for (const auto& part : p)
      if (part == "..")
        throw std::runtime_error(Q(header) + " names its data file with '..' ('" + name +
                                 "'); data files must lie beside the header (allow other places "
                                 "with --allow-outside-data)");
  }
  fs::path full = p.is_absolute() ? p : folder / p;
  CheckRegularFile(full, "the data file named by " + Q(header));
  if (!limits.allowDataOutsideFolder) {
    const fs::path dir = fs::canonical(folder), real = fs::canonical(full);
    auto rel = real.lexically_relative(dir);
    if (rel.empty() || *rel.begin() == "..")
      throw std::runtime_error(Q(header) + ": its data file '" + name +
                               "' leads (through a link) to " + Q(real) +
                               ", outside the header's folder (allow it with "
                               "--allow-outside-data)");
  }
  return full;
}

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

/// Bytes a gzip stream starting at `offset` of `file` inflates to, reading at most `need` bytes.
/// Throws when the stream is corrupt.
uint64_t GzipBytes(const fs::path& file, uint64_t offset, uint64_t need) {
  gzFile gz = gzopen(file.c_str(), "rb");
  if (!gz)
    throw std::runtime_error("cannot open " + Q(file));
  std::vector<char> buf(1 << 16);
  uint64_t total = 0;
  if (offset > 0) {
    // Skip the text header: open the file, seek past it, and inflate from there.
    gzclose(gz);
    int fd = ::open(file.c_str(), O_RDONLY);
    if (fd < 0 || ::lseek(fd, off_t(offset), SEEK_SET) != off_t(offset)) {
      if (fd >= 0)
        ::close(fd);
      throw std::runtime_error("cannot read " + Q(file));
    }
    gz = gzdopen(fd, "rb");
    if (!gz) {
      ::close(fd);
      throw std::runtime_error("cannot read " + Q(file));
    }
  }
  while (total < need) {
    int n = gzread(gz, buf.data(), unsigned(buf.size()));
    if (n < 0) {
      int err = 0;
      std::string msg = gzerror(gz, &err);
      gzclose(gz);
      throw std::runtime_error(Q(file) + ": its compressed data are corrupt (" + msg + ")");
    }
    if (n == 0)
      break;
    if (total == 0 && gzdirect(gz)) { // zlib passes data without a gzip header through as is
      gzclose(gz);
      throw std::runtime_error(Q(file) + ": its data are declared gzip but are not gzip data");
    }
    total += uint64_t(n);
  }
  gzclose(gz);
  return total;
}

/// Bytes a zlib (or gzip) stream of at most `maxIn` bytes starting at `offset` of `file` inflates
/// to, reading until `need` bytes came out or the stream or its bytes end. Throws when the stream
/// is corrupt. `complete` says whether the stream reached its end marker.
uint64_t ZlibBytes(const fs::path& header, const fs::path& file, uint64_t offset, uint64_t maxIn,
                   uint64_t need, bool& complete) {
  std::ifstream in(file, std::ios::binary);
  if (!in || !in.seekg(std::streamoff(offset)))
    throw std::runtime_error("cannot read " + Q(file));
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) // zlib or gzip header, as MetaIO's reader
    throw std::runtime_error("zlib cannot be initialised");
  std::vector<unsigned char> src(1 << 16), dst(1 << 16);
  uint64_t total = 0, read = 0;
  int rc = Z_OK;
  complete = false;
  while (total < need && rc != Z_STREAM_END) {
    if (z.avail_in == 0) {
      const uint64_t want = std::min<uint64_t>(src.size(), maxIn - read);
      if (want == 0)
        break;
      in.read(reinterpret_cast<char*>(src.data()), std::streamsize(want));
      const uint64_t got = uint64_t(in.gcount());
      if (got == 0)
        break;
      read += got;
      z.next_in = src.data();
      z.avail_in = unsigned(got);
    }
    z.next_out = dst.data();
    z.avail_out = unsigned(dst.size());
    rc = inflate(&z, Z_NO_FLUSH);
    total += dst.size() - z.avail_out;
    if (rc == Z_STREAM_END) {
      complete = true;
      break;
    }
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      const std::string msg = z.msg ? z.msg : "error " + std::to_string(rc);
      inflateEnd(&z);
      throw std::runtime_error(Q(header) + ": its compressed data are corrupt (zlib: " + msg + ")");
    }
    if (rc == Z_BUF_ERROR && z.avail_in != 0)
      break; // no progress possible
  }
  inflateEnd(&z);
  return total;
}

void CheckDataBytes(const fs::path& header, const fs::path& data, uint64_t offset, uint64_t need,
                    bool gzip) {
  uint64_t have = 0;
  if (gzip)
    have = GzipBytes(data, offset, need);
  else {
    uint64_t size = fs::file_size(data);
    have = size > offset ? size - offset : 0;
  }
  if (have < need)
    throw std::runtime_error(Q(header) + " is truncated: its voxels need " + std::to_string(need) +
                             " bytes, " + (data == header ? "the file" : Q(data)) + " holds " +
                             (gzip ? "(uncompressed) " : "") + std::to_string(have));
}

/// Read the text header lines of `file` (until `stop` says so), with the limits.
template <class Stop>
std::vector<std::string> HeaderLines(const fs::path& file, uint64_t& headerBytes, Stop stop) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot open " + Q(file));
  std::vector<std::string> lines;
  std::string line;
  headerBytes = 0;
  while (true) {
    line.clear();
    char c;
    bool got = false;
    while (in.get(c)) {
      got = true;
      if (++headerBytes > kMaxHeaderBytes)
        throw std::runtime_error(Q(file) + ": the header is longer than " +
                                 std::to_string(kMaxHeaderBytes) +
                                 " bytes (corrupt, or not an image header)");
      if (c == '\n')
        break;
      line.push_back(c);
    }
    if (!got)
      break;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    if (int(lines.size()) >= kMaxHeaderLines)
      throw std::runtime_error(Q(file) + ": the header has more than " +
                               std::to_string(kMaxHeaderLines) + " lines");
    lines.push_back(line);
    if (stop(line))
      break;
  }
  return lines;
}

/// ", with the import's working memory (N bytes per voxel)" when there is some.
std::string WorkingMemory(uint64_t extra) {
  return extra ? ", with the import's working memory (" + std::to_string(4 + extra) +
                     " bytes per voxel)"
               : std::string();
}

void CheckMemory(const fs::path& file, const VolumeHeader& h, const HeaderLimits& limits) {
  const uint64_t voxels = h.dims[0] * h.dims[1] * h.dims[2]; // each <= 10^9: product < 2^90?
  const long double exact = (long double)h.dims[0] * h.dims[1] * h.dims[2];
  const uint64_t perVoxel = sizeof(float) * uint64_t(h.components) + limits.extraBytesPerVoxel;
  const uint64_t bytes = exact * (long double)perVoxel > 1e18L ? uint64_t(1e18) : voxels * perVoxel;
  CheckMemoryBudget(bytes, limits.maxMemoryBytes,
                    "the CT " + Q(file) + " (" + std::to_string(h.dims[0]) + " x " +
                        std::to_string(h.dims[1]) + " x " + std::to_string(h.dims[2]) + " voxels" +
                        WorkingMemory(limits.extraBytesPerVoxel) + ")");
}

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

template <class T> T Get(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap)
    std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

/// NIfTI's two orientations, when both are set, must place the volume alike: readers choose
/// differently between them (ITK takes the sform), so a file whose two disagree has no one
/// geometry. Compared at the volume's 8 corners; tolerance half a voxel, at least 0.5 mm.
void CheckQformMatchesSform(const fs::path& file, const uint64_t dims[3],
                            const std::vector<double>& pixdim, const std::vector<double>& q,
                            const std::vector<double>& s) {
  // nifti1_io's nifti_quatern_to_mat44.
  double b = q[0], c = q[1], d = q[2], a = 1 - (b * b + c * c + d * d);
  if (a < 1e-7) {
    a = 1 / std::sqrt(b * b + c * c + d * d);
    b *= a;
    c *= a;
    d *= a;
    a = 0;
  } else {
    a = std::sqrt(a);
  }
  const double xd = pixdim[1] > 0 ? pixdim[1] : 1, yd = pixdim[2] > 0 ? pixdim[2] : 1;
  const double zd = (pixdim[3] > 0 ? pixdim[3] : 1) * (pixdim[0] < 0 ? -1 : 1);
  const double R[3][3] = {
      {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
      {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
      {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
  double worst = 0;
  uint64_t at[3] = {0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const double ijk[3] = {(corner & 1) ? double(dims[0] - 1) : 0.0,
                           (corner & 2) ? double(dims[1] - 1) : 0.0,
                           (corner & 4) ? double(dims[2] - 1) : 0.0};
    double dist = 0;
    for (int r = 0; r < 3; ++r) {
      const double fromQ =
          R[r][0] * xd * ijk[0] + R[r][1] * yd * ijk[1] + R[r][2] * zd * ijk[2] + q[size_t(3 + r)];
      const double fromS = s[size_t(4 * r)] * ijk[0] + s[size_t(4 * r + 1)] * ijk[1] +
                           s[size_t(4 * r + 2)] * ijk[2] + s[size_t(4 * r + 3)];
      dist += (fromQ - fromS) * (fromQ - fromS);
    }
    dist = std::sqrt(dist);
    if (dist > worst) {
      worst = dist;
      for (int k = 0; k < 3; ++k)
        at[k] = uint64_t(ijk[k]);
    }
  }
  const double tol = std::max(0.5, 0.5 * std::min({xd, yd, std::abs(zd)}));
  if (worst > tol) {
    std::ostringstream m;
    m << Q(file) << ": its qform and sform (both set) place voxel (" << at[0] << ", " << at[1]
      << ", " << at[2] << ") " << worst
      << " mm apart: the file has two different geometries and which one is right is unknown";
    throw std::runtime_error(m.str());
  }
}

VolumeHeader CheckNifti(const fs::path& file, const HeaderLimits& limits) {
  unsigned char hdr[348];
  {
    gzFile gz = gzopen(file.c_str(), "rb"); // reads plain files as they are
    if (!gz)
      throw std::runtime_error("cannot open " + Q(file));
    int n = gzread(gz, hdr, sizeof hdr);
    gzclose(gz);
    if (n != int(sizeof hdr))
      throw std::runtime_error(Q(file) + " is too short for a NIfTI header (348 bytes)");
  }
  bool swap = false;
  int32_t sz = Get<int32_t>(hdr, false);
  if (sz != 348) {
    swap = true;
    sz = Get<int32_t>(hdr, true);
  }
  if (sz != 348)
    throw std::runtime_error(Q(file) + " is not a NIfTI-1 file (its header size is not 348)");
  if (std::memcmp(hdr + 344, "n+1", 4) != 0)
    throw std::runtime_error(Q(file) + " is not a single-file NIfTI-1 image (magic n+1)");
  VolumeHeader h;
  h.format = "NIfTI";
  int16_t dim[8];
  for (int i = 0; i < 8; ++i)
    dim[i] = Get<int16_t>(hdr + 40 + 2 * i, swap);
  if (dim[0] < 1 || dim[0] > 7)
    throw std::runtime_error(Q(file) + ": invalid NIfTI dim[0] " + std::to_string(dim[0]));
  for (int i = 4; i <= dim[0]; ++i)
    if (dim[i] > 1)
      throw std::runtime_error(Q(file) + " is a " + std::to_string(dim[0]) + "-D image (axis " +
                               std::to_string(i) + " has " + std::to_string(dim[i]) +
                               " samples); a CT volume must be 3-D");
  if (dim[0] < 3)
    throw std::runtime_error(Q(file) + " is a " + std::to_string(dim[0]) +
                             "-D image; a CT volume must be 3-D");
  for (int a = 0; a < 3; ++a) {
    if (dim[a + 1] < 1)
      throw std::runtime_error(Q(file) + ": size " + std::to_string(dim[a + 1]) + " along axis " +
                               std::to_string(a) + " is not positive");
    h.dims[a] = uint64_t(dim[a + 1]);
  }
  const int16_t datatype = Get<int16_t>(hdr + 70, swap);
  static const std::map<int, std::pair<int, bool>> types = {
      {2, {1, true}},   {4, {2, true}},   {8, {4, true}},   {16, {4, false}},  {64, {8, false}},
      {256, {1, true}}, {512, {2, true}}, {768, {4, true}}, {1024, {8, true}}, {1280, {8, true}}};
  auto t = types.find(datatype);
  if (t == types.end())
    throw std::runtime_error(Q(file) + ": NIfTI datatype " + std::to_string(datatype) +
                             " is not a scalar type a CT uses");
  h.componentBytes = t->second.first;
  h.integerType = t->second.second;
  CheckMemory(file, h, limits);
  std::vector<double> pixdim;
  for (int i = 0; i < 4; ++i)
    pixdim.push_back(Get<float>(hdr + 76 + 4 * i, swap));
  CheckFinite(file, "pixdim", pixdim, 4);
  CheckSpacing(file, {std::abs(pixdim[1]), std::abs(pixdim[2]), std::abs(pixdim[3])});
  const double voxOffset = Get<float>(hdr + 108, swap);
  const double slope = Get<float>(hdr + 112, swap), inter = Get<float>(hdr + 116, swap);
  if (!std::isfinite(slope) || !std::isfinite(inter))
    throw std::runtime_error(Q(file) + " has a non-finite rescale (scl_slope " +
                             std::to_string(slope) + ", scl_inter " + std::to_string(inter) + ")");
  h.hasRescale = slope != 0 && (slope != 1 || inter != 0);
  const int16_t qcode = Get<int16_t>(hdr + 252, swap), scode = Get<int16_t>(hdr + 254, swap);
  std::vector<double> q, s;
  for (int i = 0; i < 6; ++i)
    q.push_back(Get<float>(hdr + 256 + 4 * i, swap));
  for (int i = 0; i < 12; ++i)
    s.push_back(Get<float>(hdr + 280 + 4 * i, swap));
  if (qcode > 0)
    CheckFinite(file, "qform (orientation and origin)", q, 6);
  if (scode > 0)
    CheckFinite(file, "sform (orientation and origin)", s, 12);
  if (qcode > 0 && scode > 0)
    CheckQformMatchesSform(file, h.dims, pixdim, q, s);
  if (!(voxOffset >= 348) || voxOffset > 1e9)
    throw std::runtime_error(Q(file) + ": NIfTI vox_offset " + std::to_string(voxOffset) +
                             " is not a valid data offset");
  h.dataFile = file;
  const uint64_t need =
      h.dims[0] * h.dims[1] * h.dims[2] * uint64_t(h.componentBytes) * uint64_t(h.components);
  const bool gz = Lower(file.extension().string()) == ".gz";
  if (gz) {
    const uint64_t have = GzipBytes(file, 0, uint64_t(voxOffset) + need);
    if (have < uint64_t(voxOffset) + need)
      throw std::runtime_error(
          Q(file) + " is truncated: its voxels need " + std::to_string(need) +
          " bytes after offset " + std::to_string(uint64_t(voxOffset)) +
          ", it holds (uncompressed) " +
          std::to_string(have > uint64_t(voxOffset) ? have - uint64_t(voxOffset) : 0));
  } else {
    CheckDataBytes(file, file, uint64_t(voxOffset), need, false);
  }
  return h;
}

} // namespace

void CheckRegularFile(const fs::path& path, const std::string& role) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw std::runtime_error(role + " " + Q(path) + " does not exist or cannot be opened");
  const char* kind = nullptr;
  if (S_ISDIR(st.st_mode))
    kind = "a folder";
  else if (S_ISFIFO(st.st_mode))
    kind = "a FIFO (named pipe)";
  else if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))
    kind = "a device";
  else if (S_ISSOCK(st.st_mode))
    kind = "a socket";
  else if (!S_ISREG(st.st_mode))
    kind = "not a regular file";
  const std::string why = kind ? std::string() : NotARegularFile(path.string());
  if (!kind && !why.empty()) // a kernel interface file (/proc/kmsg blocks the first read)
    kind = why.c_str();
  if (kind)
    throw std::runtime_error(role + " " + Q(path) + " is " + kind + ", not a regular file");
}

VolumeHeader CheckVolumeHeader(const fs::path& file, const std::string& format,
                               const HeaderLimits& limits) {
  CheckRegularFile(file, "the input");
  if (format == "NRRD")
    return CheckNrrd(file, limits);
  if (format == "MetaImage")
    return CheckMeta(file, limits);
  if (format == "NIfTI")
    return CheckNifti(file, limits);
  throw std::invalid_argument("CheckVolumeHeader: unknown format " + format);
}

fs::path DetachedDataFile(const fs::path& header) {
  const std::string ext = Lower(header.extension().string());
  const bool nrrd = ext == ".nrrd" || ext == ".nhdr", meta = ext == ".mha" || ext == ".mhd";
  if (!(nrrd || meta))
    return {};
  std::error_code ec;
  if (!fs::is_regular_file(header, ec))
    return {};
  try {
    uint64_t bytes = 0;
    const auto lines = HeaderLines(header, bytes, [&](const std::string& l) {
      return nrrd ? l.empty() : Lower(Trim(l)).rfind("elementdatafile", 0) == 0;
    });
    for (const std::string& line : lines) {
      const std::string l = Trim(line);
      std::string key, value;
      if (nrrd) {
        const size_t colon = l.find(": ");
        if (colon == std::string::npos || l.find(":=") != std::string::npos)
          continue;
        key = Lower(Trim(l.substr(0, colon)));
        value = Trim(l.substr(colon + 2));
        if (key != "data file" && key != "datafile")
          continue;
      } else {
        const size_t eq = l.find('=');
        if (eq == std::string::npos)
          continue;
        key = Lower(Trim(l.substr(0, eq)));
        value = Trim(l.substr(eq + 1));
        if (key != "elementdatafile" || Lower(value) == "local")
          continue;
      }
      if (value.empty() || value.find('%') != std::string::npos || value.rfind("LIST", 0) == 0)
        return {};
      const fs::path p(value);
      const fs::path folder = header.parent_path().empty() ? fs::path(".") : header.parent_path();
      return p.is_absolute() ? p : folder / p;
    }
  } catch (const std::exception&) {
  }
  return {};
}

void AddCTInputs(InputFiles& inputs, const std::string& input, const std::string& role) {
  std::error_code ec;
  if (fs::is_directory(input, ec)) {
    inputs.AddFolder(input, role + " folder");
  } else {
    inputs.AddFile(input, role);
    const fs::path data = DetachedDataFile(input);
    if (!data.empty())
      inputs.AddFile(data.string(), "the data file of " + role);
    if (NotARegularFile(input).empty() && HasDicomMagic(input)) { // a FIFO would block the read
      const fs::path folder = fs::path(input).parent_path();
      inputs.AddFolder(folder.empty() ? "." : folder.string(),
                       "the folder of " + role + "'s DICOM series");
    }
  }
}

void CheckOutputIsNotInput(const std::string& input, const std::string& output) {
  InputFiles inputs;
  AddCTInputs(inputs, input);
  try {
    inputs.CheckOutput(output, "the output");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (it would overwrite the CT)");
  }
}

} // namespace bm
