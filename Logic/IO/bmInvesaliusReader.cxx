#include "bmInvesaliusReader.h"

#include <zlib.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <regex>

namespace bm {

namespace {

/// Streams a .tar.gz: Next() moves to the next member, Read() reads its data.
class TarGzReader {
public:
  explicit TarGzReader(const std::string& path) : Path_(path) {
    F_ = gzopen(path.c_str(), "rb");
    if (!F_)
      throw std::runtime_error("cannot open '" + path + "'");
  }
  ~TarGzReader() {
    if (F_)
      gzclose(F_);
  }
  TarGzReader(const TarGzReader&) = delete;
  TarGzReader& operator=(const TarGzReader&) = delete;

  /// Advance to the next file member; false at the end of the archive.
  bool Next(std::string& name, uint64_t& size) {
    Skip(Remaining_ + Padding_);
    for (;;) {
      char h[512];
      int got = gzread(F_, h, 512);
      if (got == 0)
        return false;
      if (got != 512)
        Fail("truncated tar header");
      bool zero = true;
      for (char c : h)
        zero &= c == 0;
      if (zero)
        return false; // end-of-archive block
      name.assign(h, strnlen(h, 100));
      std::string prefix(h + 345, strnlen(h + 345, 155));
      if (std::memcmp(h + 257, "ustar", 5) == 0 && !prefix.empty())
        name = prefix + "/" + name;
      size = 0;
      for (int i = 124; i < 136 && h[i]; ++i)
        if (h[i] >= '0' && h[i] <= '7')
          size = size * 8 + uint64_t(h[i] - '0');
      char type = h[156];
      Remaining_ = size;
      Padding_ = (512 - size % 512) % 512;
      if (type == '0' || type == '\0')
        return true;
      Skip(Remaining_ + Padding_); // directories, links, extended headers
      Remaining_ = Padding_ = 0;
    }
  }
  /// Read n bytes of the current member.
  void Read(void* dst, uint64_t n) {
    if (n > Remaining_)
      Fail("member shorter than expected");
    char* p = static_cast<char*>(dst);
    while (n > 0) {
      unsigned chunk = unsigned(std::min<uint64_t>(n, 1u << 30));
      int got = gzread(F_, p, chunk);
      if (got <= 0)
        Fail("truncated or corrupt archive");
      p += got;
      n -= uint64_t(got);
      Remaining_ -= uint64_t(got);
    }
  }
  std::string ReadAll(uint64_t size) {
    std::string s(size, '\0');
    Read(s.data(), size);
    return s;
  }

private:
  void Skip(uint64_t n) {
    char buf[65536];
    while (n > 0) {
      unsigned chunk = unsigned(std::min<uint64_t>(n, sizeof buf));
      int got = gzread(F_, buf, chunk);
      if (got <= 0)
        Fail("truncated or corrupt archive");
      n -= uint64_t(got);
    }
    Remaining_ = 0;
  }
  [[noreturn]] void Fail(const std::string& why) {
    throw std::runtime_error("'" + Path_ + "' is not a readable InVesalius project: " + why);
  }
  std::string Path_;
  gzFile F_ = nullptr;
  uint64_t Remaining_ = 0, Padding_ = 0;
};

/// The few plist values main.plist holds, as text, under their key path ("matrix/shape/0").
using PlistValues = std::map<std::string, std::string>;

void ParsePlist(const std::string& xml, PlistValues& out) {
  // std::regex matches recursively: a very long tag name would exhaust the stack. main.plist's tags
  // are short words; refuse anything else before matching.
  for (size_t i = xml.find('<'); i != std::string::npos; i = xml.find('<', i + 1)) {
    size_t j = i + 1, letters = 0;
    if (j < xml.size() && xml[j] == '/')
      ++j;
    while (j < xml.size() && std::isalpha((unsigned char)xml[j]) && letters <= 64)
      ++j, ++letters;
    if (letters > 64)
      throw std::runtime_error("main.plist: a tag name is implausibly long (corrupt project)");
  }
  // A small recursive descent over <dict>, <array>, <key> and scalar elements.
  std::regex tagRe(R"(<(/?)([A-Za-z]+)(/?)>)");
  std::vector<std::pair<std::string, int>> stack; // container kind, array counter
  std::vector<std::string> path;
  std::string pendingKey;
  auto it = std::sregex_iterator(xml.begin(), xml.end(), tagRe);
  for (; it != std::sregex_iterator(); ++it) {
    const auto& m = *it;
    bool close = m[1].length() > 0, selfClose = m[3].length() > 0;
    std::string tag = m[2];
    if (tag == "plist")
      continue;
    auto childName = [&]() {
      if (!stack.empty() && stack.back().first == "array")
        return std::to_string(stack.back().second++);
      return pendingKey;
    };
    if (tag == "key" && !close) {
      size_t start = size_t(m.position() + m.length());
      size_t end = xml.find("</key>", start);
      if (end == std::string::npos)
        throw std::runtime_error("main.plist: unterminated <key>");
      pendingKey = xml.substr(start, end - start);
      continue;
    }
    if (tag == "key")
      continue;
    if (tag == "dict" || tag == "array") {
      if (close) {
        if (stack.empty())
          throw std::runtime_error("main.plist: unbalanced </" + tag + ">");
        stack.pop_back();
        if (!path.empty())
          path.pop_back();
      } else if (!selfClose) {
        if (!stack.empty())
          path.push_back(childName());
        stack.push_back({tag, 0});
      } else if (!stack.empty()) {
        childName();
      }
      continue;
    }
    if (close)
      continue;
    std::string name = childName();
    std::string value;
    if (selfClose) {
      value = tag; // <true/> <false/>
    } else {
      size_t start = size_t(m.position() + m.length());
      size_t end = xml.find("</" + tag + ">", start);
      if (end == std::string::npos)
        throw std::runtime_error("main.plist: unterminated <" + tag + ">");
      value = xml.substr(start, end - start);
    }
    std::string key;
    for (const auto& p : path)
      key += p + "/";
    out[key + name] = value;
  }
}

std::string Need(const PlistValues& v, const std::string& key, const std::string& path) {
  auto it = v.find(key);
  if (it == v.end())
    throw std::runtime_error("'" + path + "': main.plist has no '" + key + "'");
  return it->second;
}

template <class T> void ConvertSlice(const char* raw, size_t n, float* dst) {
  for (size_t i = 0; i < n; ++i) {
    T v;
    std::memcpy(&v, raw + i * sizeof(T), sizeof(T));
    dst[i] = float(v);
  }
}

} // namespace

CTImage ReadInvesaliusProject(const std::string& path, const ReadOptions& opt,
                              const Progress& progress) {
  PlistValues plist;
  {
    TarGzReader tar(path);
    std::string name;
    uint64_t size = 0;
    bool found = false;
    while (tar.Next(name, size)) {
      std::string base =
          name.substr(name.find_last_of('/') == std::string::npos ? 0 : name.find_last_of('/') + 1);
      if (base == "main.plist") {
        if (size > (1u << 20))
          throw std::runtime_error("'" + path + "': main.plist is implausibly large");
        ParsePlist(tar.ReadAll(size), plist);
        found = true;
        break;
      }
    }
    if (!found)
      throw std::runtime_error("'" + path + "' holds no main.plist: not an InVesalius project");
  }
  const std::string modality = plist.count("modality") ? plist["modality"] : "";
  if (!modality.empty() && modality != "CT" && !opt.allowNonCT)
    throw std::runtime_error("'" + path + "' has modality '" + modality + "', not CT");
  const std::string dtype = Need(plist, "matrix/dtype", path);
  const std::string file = Need(plist, "matrix/filename", path);
  size_t shape[3];
  double spacing[3];
  // A number of main.plist, refused with the key's name when it does not parse completely.
  auto number = [&](const std::string& key) {
    const std::string text = Need(plist, key, path);
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0')
      throw std::runtime_error("'" + path + "': main.plist's '" + key + "' is not a number ('" +
                               text + "')");
    return v;
  };
  for (int a = 0; a < 3; ++a) {
    const double n = number("matrix/shape/" + std::to_string(a));
    spacing[a] = number("spacing/" + std::to_string(a));
    if (!(n >= 1) || n > 1e6 || n != std::floor(n))
      throw std::runtime_error("'" + path + "': matrix shape " + std::to_string(a) + " is " +
                               std::to_string(n) + ", not a whole number 1 .. 10^6");
    shape[a] = size_t(n);
    if (!(spacing[a] > 0) || !std::isfinite(spacing[a]))
      throw std::runtime_error("'" + path + "' has a zero or invalid voxel spacing");
  }
  static const std::map<std::string, size_t> sizes = {{"int16", 2}, {"uint16", 2},  {"uint8", 1},
                                                      {"int8", 1},  {"float32", 4}, {"float64", 8},
                                                      {"<i2", 2},   {"<u2", 2}};
  auto ds = sizes.find(dtype);
  if (ds == sizes.end())
    throw std::runtime_error("'" + path + "': unsupported matrix dtype '" + dtype + "'");
  const size_t nz = shape[0], ny = shape[1], nx = shape[2];
  CheckMemoryBudget(
      uint64_t(nx) * ny * nz * (sizeof(float) + opt.extraBytesPerVoxel), opt.maxMemoryBytes,
      "the CT (" + std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz) +
          " voxels" + (opt.extraBytesPerVoxel ? ", with the import's working memory" : "") + ")");

  CTImage ct;
  ct.source = path;
  ct.format = "InVesalius";
  ct.modality = modality;
  ct.seriesDescription = plist.count("name") ? plist["name"] : "";
  ct.numFiles = 1;
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{nx, ny, nz}});
  ct.hu->SetRegions(region);
  HUImage::SpacingType sp;
  for (int a = 0; a < 3; ++a)
    sp[a] = spacing[a];
  ct.hu->SetSpacing(sp);
  ct.hu->Allocate();

  TarGzReader tar(path);
  std::string name;
  uint64_t size = 0;
  bool found = false;
  while (tar.Next(name, size)) {
    std::string base =
        name.substr(name.find_last_of('/') == std::string::npos ? 0 : name.find_last_of('/') + 1);
    if (base != file)
      continue;
    const size_t perSlice = nx * ny, bytesPerSlice = perSlice * ds->second;
    if (size != uint64_t(bytesPerSlice) * nz)
      throw std::runtime_error("'" + path + "': " + file + " holds " + std::to_string(size) +
                               " bytes, main.plist's " + "shape and dtype need " +
                               std::to_string(uint64_t(bytesPerSlice) * nz));
    std::vector<char> raw(bytesPerSlice);
    float* dst = ct.hu->GetBufferPointer();
    for (size_t k = 0; k < nz; ++k) {
      progress(double(k) / nz, "reading InVesalius project");
      tar.Read(raw.data(), bytesPerSlice);
      float* d = dst + k * perSlice;
      if (dtype == "int16" || dtype == "<i2")
        ConvertSlice<int16_t>(raw.data(), perSlice, d);
      else if (dtype == "uint16" || dtype == "<u2")
        ConvertSlice<uint16_t>(raw.data(), perSlice, d);
      else if (dtype == "uint8")
        ConvertSlice<uint8_t>(raw.data(), perSlice, d);
      else if (dtype == "int8")
        ConvertSlice<int8_t>(raw.data(), perSlice, d);
      else if (dtype == "float32")
        ConvertSlice<float>(raw.data(), perSlice, d);
      else
        ConvertSlice<double>(raw.data(), perSlice, d);
    }
    found = true;
    break;
  }
  if (!found)
    throw std::runtime_error("'" + path + "' does not hold the matrix file '" + file + "'");
  progress(1.0, "reading InVesalius project");
  UpdateHURange(ct);
  return ct;
}

} // namespace bm
