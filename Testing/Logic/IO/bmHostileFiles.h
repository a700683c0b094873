// bmHostileFiles.h - generators of the hostile-input corpus (Docs/Reliability.md): small volume
// files made by the tests (no binary blobs in the repository). Each generator makes a valid
// 4 x 4 x 4 image by default; the caller changes one thing to make it hostile. Used by the
// in-process corpus (TestHostileInput.cxx) and the bmsim corpus (TestBmsimHostileCorpus.cxx).
#pragma once

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace bmtest {

/// `count` int16 voxels: air (-1000) with a block of bone (1000) in each 64.
inline std::string Voxels(size_t count = 64) {
  std::string s;
  for (size_t i = 0; i < count; ++i) {
    const int16_t v = (i % 64 >= 21 && i % 64 <= 42) ? 1000 : -1000;
    s.append(reinterpret_cast<const char*>(&v), 2);
  }
  return s;
}

inline void WriteFile(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
}

inline std::string ReadFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void WriteGzip(const std::filesystem::path& p, const std::string& bytes) {
  gzFile gz = gzopen(p.c_str(), "wb");
  gzwrite(gz, bytes.data(), unsigned(bytes.size()));
  gzclose(gz);
}

/// A NRRD header from fields (in order; "-" drops a default field), attached data after it
/// unless a field names a data file.
inline std::string Nrrd(std::map<std::string, std::string> over,
                        const std::string& data = Voxels()) {
  std::vector<std::pair<std::string, std::string>> f = {{"type", "short"},    {"dimension", "3"},
                                                        {"sizes", "4 4 4"},   {"spacings", "1 1 1"},
                                                        {"endian", "little"}, {"encoding", "raw"}};
  for (auto& [k, v] : f)
    if (over.count(k)) {
      v = over[k];
      over.erase(k);
    }
  std::string s = "NRRD0004\n";
  for (const auto& [k, v] : f)
    if (v != "-")
      s += k + ": " + v + "\n";
  bool detached = false;
  for (const auto& [k, v] : over) {
    if (k == "data file")
      detached = true;
    if (v != "-")
      s += k + ": " + v + "\n";
  }
  s += "\n";
  return detached ? s : s + data;
}

/// A MetaImage (.mha) with LOCAL data unless ElementDataFile is given.
inline std::string Mha(std::map<std::string, std::string> over,
                       const std::string& data = Voxels()) {
  std::vector<std::pair<std::string, std::string>> f = {
      {"ObjectType", "Image"},     {"NDims", "3"},
      {"DimSize", "4 4 4"},        {"ElementType", "MET_SHORT"},
      {"ElementSpacing", "1 1 1"}, {"Offset", "0 0 0"},
      {"BinaryData", "True"},      {"BinaryDataByteOrderMSB", "False"}};
  for (auto& [k, v] : f)
    if (over.count(k)) {
      v = over[k];
      over.erase(k);
    }
  std::string file = "LOCAL";
  if (over.count("ElementDataFile")) {
    file = over["ElementDataFile"];
    over.erase("ElementDataFile");
  }
  std::string s;
  for (const auto& [k, v] : f)
    s += k + " = " + v + "\n";
  for (const auto& [k, v] : over)
    s += k + " = " + v + "\n";
  s += "ElementDataFile = " + file + "\n";
  return file == "LOCAL" ? s + data : s;
}

inline void PutFloat(char* h, int off, float v) {
  std::memcpy(h + off, &v, 4);
}
inline void PutShort(char* h, int off, int16_t v) {
  std::memcpy(h + off, &v, 2);
}

/// A single-file NIfTI-1 image; `edit` changes the 348-byte header before it is written.
inline std::string Nifti(const std::function<void(char*)>& edit = {},
                         const std::string& data = Voxels()) {
  char h[352] = {};
  const int32_t headerSize = 348;
  std::memcpy(h, &headerSize, 4);
  const int16_t dim[8] = {3, 4, 4, 4, 1, 1, 1, 1};
  for (int i = 0; i < 8; ++i)
    PutShort(h, 40 + 2 * i, dim[i]);
  PutShort(h, 70, 4);  // datatype int16
  PutShort(h, 72, 16); // bitpix
  for (int i = 0; i < 8; ++i)
    PutFloat(h, 76 + 4 * i, 1.0f);
  PutFloat(h, 108, 352); // vox_offset
  PutFloat(h, 112, 1);   // scl_slope
  PutFloat(h, 116, 0);   // scl_inter
  std::memcpy(h + 344, "n+1", 4);
  if (edit)
    edit(h);
  return std::string(h, sizeof h) + data;
}

/// A saved voxmap's MetaImage: 4 x 4 x 4 voxels of (bone fraction 1, `material`), voxel index
/// `at` given `bad` instead.
inline std::string VoxmapMha(float material, int at = -1, float bad = 1.0f,
                             std::map<std::string, std::string> over = {}) {
  std::string data;
  for (int i = 0; i < 64; ++i) {
    const float v[2] = {1.0f, i == at ? bad : material};
    data.append(reinterpret_cast<const char*>(v), sizeof v);
  }
  over.emplace("ElementType", "MET_FLOAT");
  over.emplace("ElementNumberOfChannels", "2");
  return Mha(over, data);
}

/// One ustar member: a 512-byte header and the data padded to 512 bytes.
inline std::string TarMember(const std::string& name, const std::string& data) {
  char h[512] = {};
  std::memcpy(h, name.data(), std::min<size_t>(name.size(), 99));
  std::snprintf(h + 100, 8, "%07o", 0644);
  std::snprintf(h + 124, 12, "%011llo", (unsigned long long)data.size());
  h[156] = '0';
  std::memcpy(h + 257, "ustar", 5);
  std::string out(h, sizeof h);
  out += data;
  out.append((512 - data.size() % 512) % 512, '\0');
  return out;
}

/// main.plist of an InVesalius project with `shape` (z y x) and `spacing`, int16 matrix.dat.
inline std::string
Plist(const std::string& shape = "<integer>4</integer><integer>4</integer>"
                                 "<integer>4</integer>",
      const std::string& spacing = "<real>1</real><real>1</real><real>1</real>") {
  return "<?xml version=\"1.0\"?><plist version=\"1.0\"><dict><key>modality</key><string>CT"
         "</string><key>matrix</key><dict><key>dtype</key><string>int16</string><key>filename"
         "</key><string>matrix.dat</string><key>shape</key><array>" +
         shape + "</array></dict><key>spacing</key><array>" + spacing + "</array></dict></plist>";
}

/// An InVesalius project's tar (gzip it with WriteGzip).
inline std::string Inv3(const std::string& plist = Plist(), const std::string& matrix = Voxels()) {
  return TarMember("project/main.plist", plist) + TarMember("project/matrix.dat", matrix) +
         std::string(1024, '\0');
}

} // namespace bmtest
