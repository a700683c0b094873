// bmFrameRecord.h - what the session records each frame, and the lock-free single-producer /
// single-consumer ring that carries records from the haptic thread to a recorder without the
// haptic thread ever waiting (when the ring is full the record is dropped and counted).
//
// Units: s, mm, N, N mm, mm/rev, rpm, ms, mm^3.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace bm {

struct FrameRecord {
  int64_t frame = 0;                 ///< frame number since Start (paused frames not counted)
  double timeS = 0;                  ///< session time, s (frame * period)
  std::array<double, 3> devicePos{}; ///< device tool position, world mm
  std::array<double, 4> deviceQuat{1, 0, 0,
                                   0}; ///< device tool orientation (w, x, y, z), tool -> world
  std::array<double, 3> proxyPos{};    ///< proxy position, world mm
  double feedMmPerRev = 0;
  double thrustN = 0;
  double torqueNmm = 0;
  std::array<double, 3> couplingForce{}; ///< on the proxy, N
  std::array<double, 3> deviceForce{};   ///< sent to the device (clamped, world), N
  double frameMs = 0;                    ///< compute time of the frame, ms
  int64_t removedVoxels = 0;
  double removedVolumeMm3 = 0;
  double speedRpm = 0; ///< spindle speed this frame, rpm
  uint32_t buttons = 0;
  uint32_t flags = 0; ///< kResumed: first frame after a pause
  static constexpr uint32_t kResumed = 1;

  /// Column names, in the order of ToRow/FromRow (CSV header and HDF5 "columns" attribute).
  static const std::vector<std::string>& Columns();
  std::vector<double> ToRow() const;
  /// Throws std::invalid_argument if the row is shorter than Columns(), or a whole-number column
  /// (frame, removed_voxels, buttons, flags) is not finite, not whole or out of its type's range,
  /// naming the column.
  static FrameRecord FromRow(const std::vector<double>& row);
};

/// Rotation matrix of a recorded (w, x, y, z) quaternion; the session and the replay both build
/// the tool orientation this way, so a replay is bit-identical.
Eigen::Matrix3d ToolRotationFromQuaternion(const std::array<double, 4>& wxyz);

/// Fixed-capacity SPSC ring. Push only from one thread, Pop only from one (other) thread.
class RecordRing {
public:
  /// capacity: records held (rounded up to a power of two, >= 2).
  explicit RecordRing(size_t capacity = 1 << 16);
  /// Producer: false (and Dropped() grows) when full. Never blocks.
  bool Push(const FrameRecord& r);
  /// Consumer: moves every available record to `out`; returns how many.
  size_t Drain(std::vector<FrameRecord>& out);
  uint64_t Dropped() const { return Dropped_.load(std::memory_order_relaxed); }

private:
  std::vector<FrameRecord> Buf_;
  size_t Mask_;
  alignas(64) std::atomic<uint64_t> Head_{0}; // next to write
  alignas(64) std::atomic<uint64_t> Tail_{0}; // next to read
  std::atomic<uint64_t> Dropped_{0};
};

} // namespace bm
