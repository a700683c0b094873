// bmTimingStats.h - frame-time statistics kept by the haptic thread without allocating: a
// histogram of 1 us bins up to 50 ms (longer frames fall in the last bin; the maximum is exact).
//
// Units: ms.
#pragma once

#include <cstdint>
#include <vector>

namespace bm {

struct TimingStats {
  int64_t frames = 0;
  double p50Ms = 0, p99Ms = 0, maxMs = 0, meanMs = 0; ///< frame compute time, ms
  int64_t overruns = 0;                               ///< frames longer than the period
};

class TimingHistogram {
public:
  TimingHistogram() : Bins_(kBins, 0) {}
  /// Adds a frame of ms milliseconds; overrun: it exceeded the period.
  void Add(double ms, bool overrun);
  /// Percentiles (nearest rank at 1 us), maximum, mean, overruns.
  TimingStats Stats() const;
  void Clear();

private:
  static constexpr int kBins = 50000; // 1 us each
  std::vector<uint32_t> Bins_;
  int64_t N_ = 0, Overruns_ = 0;
  double Max_ = 0, Sum_ = 0;
};

} // namespace bm
