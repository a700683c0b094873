// bmHeaderCheckFields.cxx - checks of a volume header's fields: numbers and sizes as they parse,
// finite values, the voxel spacing's range, and the memory the voxels need
// (bmHeaderCheckInternal.h).
#include "bmHeaderCheckInternal.h"

#include "bmMemoryBudget.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace fs = std::filesystem;

namespace bm::headercheck {

/// Numbers in `s` separated by blanks, commas or parentheses ("nan" and "inf" parse, as non-finite
/// values the callers refuse). Words such as "none" are returned in `words`.
std::vector<double> Numbers(const std::string& s, std::vector<std::string>* words) {
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

namespace {

/// ", with the import's working memory (N bytes per voxel)" when there is some.
std::string WorkingMemory(uint64_t extra) {
  return extra ? ", with the import's working memory (" + std::to_string(4 + extra) +
                     " bytes per voxel)"
               : std::string();
}

} // namespace

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

} // namespace bm::headercheck
