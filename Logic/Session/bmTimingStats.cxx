#include "bmTimingStats.h"

#include <algorithm>
#include <cmath>

namespace bm {

void TimingHistogram::Add(double ms, bool overrun) {
  const int b = std::clamp(int(ms * 1000.0), 0, kBins - 1);
  ++Bins_[size_t(b)];
  ++N_;
  Overruns_ += overrun;
  Max_ = std::max(Max_, ms);
  Sum_ += ms;
}

TimingStats TimingHistogram::Stats() const {
  TimingStats s;
  s.frames = N_;
  s.overruns = Overruns_;
  s.maxMs = Max_;
  s.meanMs = N_ ? Sum_ / double(N_) : 0.0;
  if (!N_)
    return s;
  auto pct = [&](double p) {
    const int64_t rank = std::max<int64_t>(1, int64_t(std::ceil(p / 100.0 * double(N_))));
    int64_t c = 0;
    for (int b = 0; b < kBins; ++b) {
      c += Bins_[size_t(b)];
      if (c >= rank)
        return std::min(Max_, (b + 1) / 1000.0); // the bin's upper edge
    }
    return Max_;
  };
  s.p50Ms = pct(50);
  s.p99Ms = pct(99);
  return s;
}

void TimingHistogram::Clear() {
  std::fill(Bins_.begin(), Bins_.end(), 0u);
  N_ = Overruns_ = 0;
  Max_ = Sum_ = 0;
}

} // namespace bm
