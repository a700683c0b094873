#include "bmFeedBalance.h"

#include <algorithm>
#include <cmath>

namespace bm {

FeedBalance::FeedBalance(const ToolModel& tool, const ForceModel& model, double fMin, double fMax)
    : Tool_(tool), Model_(model), FMin_(fMin), FMax_(fMax) {}

void FeedBalance::Rebuild(double n) {
  constexpr int kN = 40; // 40 feeds x 100 panels: a few ms, once per spindle speed
  LogF_.resize(kN);
  LogT_.resize(kN);
  for (int i = 0; i < kN; ++i) {
    const double lf = std::log(FMin_) + (std::log(FMax_) - std::log(FMin_)) * i / (kN - 1);
    const double t =
        IntegrateEdges(Tool_, Model_, std::exp(lf), n, 1e300, EdgeKind::None, 100).thrustN;
    LogF_[size_t(i)] = lf;
    LogT_[size_t(i)] = std::log(std::max(t, 1e-300));
  }
  Speed_ = n;
}

double FeedBalance::FullThrust(double f, double n) {
  if (n != Speed_)
    Rebuild(n);
  if (!(f > 0))
    return 0;
  const double lf = std::clamp(std::log(f), LogF_.front(), LogF_.back());
  auto it = std::upper_bound(LogF_.begin(), LogF_.end(), lf);
  const size_t i = std::clamp<size_t>(size_t(it - LogF_.begin()), 1, LogF_.size() - 1);
  const double u = (lf - LogF_[i - 1]) / (LogF_[i] - LogF_[i - 1]);
  double t = std::exp(LogT_[i - 1] + u * (LogT_[i] - LogT_[i - 1]));
  if (f > FMax_)
    t *= f / FMax_; // beyond the table: linear in f
  if (f < FMin_)
    t *= f / FMin_;
  return t;
}

double FeedBalance::SolveAdvance(double s, double f0, double c, double n, double T, double uMax) {
  if (!(f0 > 0) || !(s > 0) || !(n > 0) || !(uMax > 0))
    return 0;
  auto g = [&](double u) { return s * FullThrust(60.0 * u / (n * T), n) - (f0 - c * u); };
  if (g(uMax) <= 0)
    return uMax;
  double lo = 0, hi = uMax;
  for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

} // namespace bm
