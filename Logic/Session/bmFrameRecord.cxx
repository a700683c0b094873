#include "bmFrameRecord.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

namespace bm {

const std::vector<std::string>& FrameRecord::Columns() {
  static const std::vector<std::string> c = {
      "frame",         "time_s",        "device_x_mm",     "device_y_mm",        "device_z_mm",
      "device_qw",     "device_qx",     "device_qy",       "device_qz",          "proxy_x_mm",
      "proxy_y_mm",    "proxy_z_mm",    "feed_mm_per_rev", "thrust_N",           "torque_Nmm",
      "coupling_fx_N", "coupling_fy_N", "coupling_fz_N",   "device_fx_N",        "device_fy_N",
      "device_fz_N",   "frame_ms",      "removed_voxels",  "removed_volume_mm3", "speed_rpm",
      "buttons",       "flags"};
  return c;
}

std::vector<double> FrameRecord::ToRow() const {
  return {double(frame),
          timeS,
          devicePos[0],
          devicePos[1],
          devicePos[2],
          deviceQuat[0],
          deviceQuat[1],
          deviceQuat[2],
          deviceQuat[3],
          proxyPos[0],
          proxyPos[1],
          proxyPos[2],
          feedMmPerRev,
          thrustN,
          torqueNmm,
          couplingForce[0],
          couplingForce[1],
          couplingForce[2],
          deviceForce[0],
          deviceForce[1],
          deviceForce[2],
          frameMs,
          double(removedVoxels),
          removedVolumeMm3,
          speedRpm,
          double(buttons),
          double(flags)};
}

namespace {
// A whole-number column (frame, counts, bit sets) read from a double: refused unless finite, whole
// and within [lo, hi] (converting NaN or an out-of-range double to an integer is undefined).
double WholeNumber(double x, double lo, double hi, const char* column) {
  if (!(x >= lo && x <= hi) || x != std::floor(x)) {
    std::ostringstream m;
    m << "column '" << column << "' must be a whole number in [" << lo << ", " << hi << "], got "
      << x;
    throw std::invalid_argument(m.str());
  }
  return x;
}
constexpr double kMaxCount = 9.0e15; // exact in a double, far beyond any session
} // namespace

FrameRecord FrameRecord::FromRow(const std::vector<double>& v) {
  if (v.size() < Columns().size())
    throw std::invalid_argument("frame record row has too few columns");
  FrameRecord r;
  size_t i = 0;
  r.frame = int64_t(WholeNumber(v[i++], 0, kMaxCount, "frame"));
  r.timeS = v[i++];
  for (auto& x : r.devicePos)
    x = v[i++];
  for (auto& x : r.deviceQuat)
    x = v[i++];
  for (auto& x : r.proxyPos)
    x = v[i++];
  r.feedMmPerRev = v[i++];
  r.thrustN = v[i++];
  r.torqueNmm = v[i++];
  for (auto& x : r.couplingForce)
    x = v[i++];
  for (auto& x : r.deviceForce)
    x = v[i++];
  r.frameMs = v[i++];
  r.removedVoxels = int64_t(WholeNumber(v[i++], -kMaxCount, kMaxCount, "removed_voxels"));
  r.removedVolumeMm3 = v[i++];
  r.speedRpm = v[i++];
  r.buttons = uint32_t(WholeNumber(v[i++], 0, 4294967295.0, "buttons"));
  r.flags = uint32_t(WholeNumber(v[i++], 0, 4294967295.0, "flags"));
  return r;
}

Eigen::Matrix3d ToolRotationFromQuaternion(const std::array<double, 4>& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

RecordRing::RecordRing(size_t capacity) {
  size_t c = 2;
  while (c < capacity)
    c <<= 1;
  Buf_.resize(c);
  Mask_ = c - 1;
}

bool RecordRing::Push(const FrameRecord& r) {
  const uint64_t head = Head_.load(std::memory_order_relaxed);
  if (head - Tail_.load(std::memory_order_acquire) >= Buf_.size()) {
    Dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  Buf_[head & Mask_] = r;
  Head_.store(head + 1, std::memory_order_release);
  return true;
}

size_t RecordRing::Drain(std::vector<FrameRecord>& out) {
  const uint64_t tail = Tail_.load(std::memory_order_relaxed);
  const uint64_t head = Head_.load(std::memory_order_acquire);
  for (uint64_t i = tail; i < head; ++i)
    out.push_back(Buf_[i & Mask_]);
  Tail_.store(head, std::memory_order_release);
  return size_t(head - tail);
}

} // namespace bm
