#include "bmReplay.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "bmVirtualCoupling.h"

namespace bm {

Scene RecordedScene(const Recording& rec) {
  if (!rec.meta.contains("scene"))
    throw std::runtime_error("the recording has no scene");
  return Scene::FromJson(rec.meta.at("scene"));
}

ReplayResult Replay(const Recording& rec, MachiningSetup& setup) {
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
    out.replayed.push_back(q);
    ++out.frames;
  }
  return out;
}

} // namespace bm
