#include "bmReplay.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bmVirtualCoupling.h"

namespace bm {

Scene RecordedScene(const Recording& rec) {
  if (!rec.meta.contains("scene"))
    throw std::runtime_error("the recording has no scene");
  Scene s = Scene::FromJson(rec.meta.at("scene"));
  if (rec.meta.contains("scene_base_dir") && rec.meta.at("scene_base_dir").is_string())
    s.baseDir = rec.meta.at("scene_base_dir").get<std::string>();
  return s;
}

void CheckReplayable(const Recording& rec) {
  if (rec.frames.empty())
    throw std::runtime_error("the recording has no frames");
  auto finite = [](const auto& a) {
    for (double x : a)
      if (!std::isfinite(x))
        return false;
    return true;
  };
  for (size_t i = 0; i < rec.frames.size(); ++i) {
    const FrameRecord& r = rec.frames[i];
    const char* bad = !finite(r.devicePos)                 ? "device position"
                      : !finite(r.deviceQuat)              ? "device orientation"
                      : !std::isfinite(r.speedRpm)         ? "spindle speed"
                      : !finite(r.couplingForce)           ? "coupling force"
                      : !finite(r.deviceForce)             ? "device force"
                      : !std::isfinite(r.thrustN)          ? "thrust"
                      : !std::isfinite(r.torqueNmm)        ? "torque"
                      : !finite(r.proxyPos)                ? "proxy position"
                      : !std::isfinite(r.feedMmPerRev)     ? "feed"
                      : !std::isfinite(r.removedVolumeMm3) ? "removed volume"
                      : !std::isfinite(r.timeS)            ? "time"
                                                           : nullptr;
    if (bad)
      throw std::runtime_error("frame " + std::to_string(i) +
                               " of the recording has a non-finite " + bad);
  }
  // The frames are the session's, in order: numbered 0, 1, 2, ... (a pause does not count), at
  // time frame / rate. A gap, a repeat or an edited number or time is not what the session ran.
  DeviceLimits limits;
  const double rate =
      SessionOptionsFromJson(rec.meta.value("session", nlohmann::json::object()), limits).rateHz;
  for (size_t i = 0; i < rec.frames.size(); ++i) {
    const FrameRecord& r = rec.frames[i];
    if (r.frame != int64_t(i))
      throw std::runtime_error("frame " + std::to_string(i) + " of the recording is numbered " +
                               std::to_string(r.frame) +
                               ": a recording's frames are numbered 0, 1, 2, ... (a frame is "
                               "missing, repeated or renumbered)");
    const double t = double(r.frame) / rate;
    if (std::abs(r.timeS - t) > 1e-9 * std::max(1.0, t)) {
      std::ostringstream os;
      os.precision(12);
      os << "frame " << i << " of the recording is at time " << r.timeS << " s, not " << t
         << " s (frame / the session's " << rate << " Hz)";
      throw std::runtime_error(os.str());
    }
  }
}

std::vector<std::string> ReplayResult::Differing(double tolerance) const {
  std::vector<std::string> v;
  const std::pair<double, const char*> continuous[] = {{maxCouplingForceDiffN, "coupling force"},
                                                       {maxDeviceForceDiffN, "device force"},
                                                       {maxThrustDiffN, "thrust"},
                                                       {maxTorqueDiffNmm, "torque"},
                                                       {maxProxyDiffMm, "proxy position"},
                                                       {maxFeedDiffMmPerRev, "feed"},
                                                       {maxRemovedVolumeDiffMm3, "removed volume"}};
  for (const auto& [diff, name] : continuous)
    if (!(diff <= tolerance))
      v.push_back(name);
  if (maxRemovedVoxelsDiff != 0)
    v.push_back("removed voxels");
  return v;
}

ReplayResult Replay(const Recording& rec, MachiningSetup& setup) {
  CheckReplayable(rec);
  DeviceLimits limits;
  const SessionOptions o =
      SessionOptionsFromJson(rec.meta.value("session", nlohmann::json::object()), limits);
  Proxy proxy(setup, limits, 1.0 / o.rateHz, o.proxy);
  // The session warmed its proxy up the same way before its first frame.
  proxy.Prepare(rec.frames.empty() ? 0.0 : rec.frames.front().speedRpm);
  ReplayResult out;
  auto diff3 = [](const std::array<double, 3>& a, const Eigen::Vector3d& b) {
    return (Eigen::Vector3d(a[0], a[1], a[2]) - b).norm();
  };
  for (const FrameRecord& r : rec.frames) {
    if (r.flags & FrameRecord::kResumed)
      proxy.ForgetDeviceMotion();
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::Vector3d xd(r.devicePos[0], r.devicePos[1], r.devicePos[2]);
    const ProxyFrame f = proxy.Step(xd, ToolRotationFromQuaternion(r.deviceQuat), r.speedRpm);
    const Eigen::Vector3d fDev = VirtualCoupling::Clamp(f.deviceForceN, limits.maxForceN);
    FrameRecord q = r;
    q.frameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    q.proxyPos = {f.proxyPositionMm(0), f.proxyPositionMm(1), f.proxyPositionMm(2)};
    q.feedMmPerRev = f.feedMmPerRev;
    q.thrustN = f.thrustN;
    q.torqueNmm = f.torqueNmm;
    q.couplingForce = {f.couplingForceN(0), f.couplingForceN(1), f.couplingForceN(2)};
    q.deviceForce = {fDev(0), fDev(1), fDev(2)};
    q.removedVoxels = f.removedVoxels;
    q.removedVolumeMm3 = f.removedVolumeMm3;
    out.maxCouplingForceDiffN =
        std::max(out.maxCouplingForceDiffN, diff3(r.couplingForce, f.couplingForceN));
    out.maxDeviceForceDiffN = std::max(out.maxDeviceForceDiffN, diff3(r.deviceForce, fDev));
    out.maxThrustDiffN = std::max(out.maxThrustDiffN, std::abs(r.thrustN - f.thrustN));
    out.maxTorqueDiffNmm = std::max(out.maxTorqueDiffNmm, std::abs(r.torqueNmm - f.torqueNmm));
    out.maxProxyDiffMm = std::max(out.maxProxyDiffMm, diff3(r.proxyPos, f.proxyPositionMm));
    out.maxFeedDiffMmPerRev =
        std::max(out.maxFeedDiffMmPerRev, std::abs(r.feedMmPerRev - f.feedMmPerRev));
    out.maxRemovedVolumeDiffMm3 =
        std::max(out.maxRemovedVolumeDiffMm3, std::abs(r.removedVolumeMm3 - f.removedVolumeMm3));
    out.maxRemovedVoxelsDiff = std::max<int64_t>(
        out.maxRemovedVoxelsDiff, std::abs(int64_t(r.removedVoxels) - int64_t(f.removedVoxels)));
    out.replayed.push_back(q);
    ++out.frames;
  }
  return out;
}

} // namespace bm
