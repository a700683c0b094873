// bmCheckRange.h - refusing a value outside its range with a message that names it and the range
// (Docs/Reliability.md).
#pragma once

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace bm {

/// Throws std::invalid_argument "WHAT must be in [lo, hi], not v" unless v is finite and within
/// [lo, hi] (in the caller's units, which `what` should name).
inline void CheckRange(const char* what, double v, double lo, double hi) {
  if (std::isfinite(v) && v >= lo && v <= hi)
    return;
  std::ostringstream m;
  m << what << " must be in [" << lo << ", " << hi << "], not " << v;
  throw std::invalid_argument(m.str());
}

} // namespace bm
