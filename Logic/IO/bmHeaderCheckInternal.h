// bmHeaderCheckInternal.h - private to the header check (bmHeaderCheck.h), shared by its parts:
// text helpers and the text header's lines, the field checks (bmHeaderCheckFields.cxx), the data
// file's place and bytes (bmHeaderCheckData.cxx) and each format's check (bmHeaderCheckNrrd.cxx,
// bmHeaderCheckMeta.cxx, bmHeaderCheckNifti.cxx). Not part of BMIO's interface: include it only
// from those files and bmHeaderCheck.cxx.
#pragma once

#include "bmHeaderCheck.h"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace bm::headercheck {

inline std::string Q(const std::filesystem::path& p) {
  // Appended piece by piece: GCC 12 reports a false -Wrestrict for "'" + std::string&&.
  std::string q = "'";
  q += p.string();
  q += '\'';
  return q;
}

inline std::string Lower(std::string s) {
  for (auto& c : s)
    c = char(std::tolower((unsigned char)c));
  return s;
}

inline std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace((unsigned char)s[a]))
    ++a;
  while (b > a && (std::isspace((unsigned char)s[b - 1]) || s[b - 1] == '\0'))
    --b;
  return s.substr(a, b - a);
}

/// Read the text header lines of `file` (until `stop` says so), with the limits.
template <class Stop>
std::vector<std::string> HeaderLines(const std::filesystem::path& file, uint64_t& headerBytes,
                                     Stop stop) {
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

// ---------------------------------------------------------------------------------------------
// Fields (bmHeaderCheckFields.cxx)

/// Numbers in `s` separated by blanks, commas or parentheses ("nan" and "inf" parse, as non-finite
/// values the callers refuse). Words such as "none" are returned in `words`.
std::vector<double> Numbers(const std::string& s, std::vector<std::string>* words = nullptr);

/// The `count` sizes of field `field` (whole numbers 1 .. 10^9); the first three into `dims`.
void Sizes(const std::filesystem::path& file, const std::string& field, const std::string& value,
           int count, uint64_t dims[3]);

/// Throw unless `v` holds at least `count` numbers, all finite; `what` names them.
void CheckFinite(const std::filesystem::path& file, const std::string& what,
                 const std::vector<double>& v, size_t count);

// Smallest voxel spacing accepted (mm): 0.1 um, far below any scanner's; a denormal spacing makes
// the image's direction-times-spacing matrix singular for ITK.
constexpr double kMinSpacingMm = 1e-4;

/// Throw unless the three spacings `s` are finite and in [kMinSpacingMm, 10 000] mm.
void CheckSpacing(const std::filesystem::path& file, const std::vector<double>& s);

/// Throw when the image's voxels as float (with the caller's extra bytes per voxel) exceed the
/// memory limit (CheckMemoryBudget).
void CheckMemory(const std::filesystem::path& file, const VolumeHeader& h,
                 const HeaderLimits& limits);

// ---------------------------------------------------------------------------------------------
// The data file (bmHeaderCheckData.cxx)

/// Resolve a detached data file named in a header, refusing paths that leave the header's folder.
std::filesystem::path DataFileBeside(const std::filesystem::path& header, const std::string& name,
                                     const HeaderLimits& limits);

/// Bytes a gzip stream starting at `offset` of `file` inflates to, reading at most `need` bytes.
/// Throws when the stream is corrupt.
uint64_t GzipBytes(const std::filesystem::path& file, uint64_t offset, uint64_t need);

/// Bytes a zlib (or gzip) stream of at most `maxIn` bytes starting at `offset` of `file` inflates
/// to, reading until `need` bytes came out or the stream or its bytes end. Throws when the stream
/// is corrupt. `complete` says whether the stream reached its end marker.
uint64_t ZlibBytes(const std::filesystem::path& header, const std::filesystem::path& file,
                   uint64_t offset, uint64_t maxIn, uint64_t need, bool& complete);

/// Throw when `data` holds fewer than `need` bytes of voxels from `offset` on (gzip: inflated),
/// naming `header` as truncated.
void CheckDataBytes(const std::filesystem::path& header, const std::filesystem::path& data,
                    uint64_t offset, uint64_t need, bool gzip);

// ---------------------------------------------------------------------------------------------
// The formats (bmHeaderCheckNrrd.cxx, bmHeaderCheckMeta.cxx, bmHeaderCheckNifti.cxx)

/// A NRRD header (.nrrd/.nhdr), its data file and its bytes.
VolumeHeader CheckNrrd(const std::filesystem::path& file, const HeaderLimits& limits);

/// A MetaImage header (.mha/.mhd), its data file and its bytes (inflated when compressed).
VolumeHeader CheckMeta(const std::filesystem::path& file, const HeaderLimits& limits);

/// A NIfTI-1 single-file image (.nii/.nii.gz): its header, its two orientations and its bytes.
VolumeHeader CheckNifti(const std::filesystem::path& file, const HeaderLimits& limits);

} // namespace bm::headercheck
