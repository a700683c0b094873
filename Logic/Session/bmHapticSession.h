// bmHapticSession.h - a haptic session: voxmap, tool, force model and backend (a MachiningSetup),
// a device and the proxy (bmProxy.h), run on a dedicated thread at a set rate (1 kHz default).
//
// Threads: Start() opens the device and starts the haptic thread; Pause()/Resume() are honoured at
// the next frame; Stop() stops and joins the thread, sends zero force and closes the device (the
// destructor calls it). Flags are std::atomic. Other threads (GUI, recorders) read Snapshot(),
// a double buffer of two slots each behind its own mutex: the haptic thread writes the slot not
// last published with try_lock, so it never waits (if a reader holds that slot the frame's
// snapshot is skipped), and readers copy the last published slot. Per-frame records go through a
// lock-free ring (bmFrameRecord.h) that DrainRecords() empties.
//
// Each frame: device Advance/Read -> device-to-world mapping -> Proxy::Step -> device Write of the
// clamped coupling force (mapped back) -> timing, record, snapshot. Frame time is the compute
// time from the read to the write; a frame longer than the period is an overrun.
//
// Safety (Docs/Session.md): when more than `overrunLimit` frames of the last `overrunWindow`
// overran, or the device reports an error, stops answering or gives a non-finite pose, or the frame
// throws, or the session runs away (the device more than runawayDistanceMm from the proxy, or the
// proxy more than runawayMarginMm outside the bone's box), the session sends zero force in that
// same frame (the force is gone within one frame) and pauses; the cut, the proxy and the records
// are kept and Resume() goes on from them. A device error is final: Resume() refuses it and no
// non-zero force is sent again. The first startWarmupFrames frames after Start() do not count
// toward the overrun rule; after a resume the overrun window starts empty and the first
// resumeWarmupFrames frames do not count toward the rule; the proxy's target moves from where the
// proxy is toward the device at no more than catchUpSpeedMmPerS (a device moved while paused is
// followed, swept, over frames, never in one jump).
//
// Units: Hz, s, ms, mm, N, N mm, rpm, mm/rev, mm^3.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bmDevice.h"
#include "bmFrameRecord.h"
#include "bmMachiningSetup.h"
#include "bmProxy.h"
#include "bmTimingStats.h"

namespace bm {

enum class SessionState { Idle, Running, Paused, Stopped };
enum class PauseReason {
  None,
  User,
  Finished,
  Overrun,
  DeviceError, ///< the device reported an error or a non-finite pose (final: no resume)
  DeviceSilent,
  FrameError,
  Runaway ///< device far from the proxy, or the proxy far outside the bone's region
};
const char* ToString(SessionState s);
const char* ToString(PauseReason r);

struct SessionOptions {
  double rateHz = 1000; ///< haptic rate, Hz (the frame period is 1 / rate)
  ProxyOptions proxy;   ///< contact method, rendering, coupling
  double speedRpm = -1; ///< spindle speed, rpm; < 0 = the scene's trial speed (default)
  /// Device -> world: x_world = offset + scale * rotation * x_device; tool -> world orientation =
  /// rotation * stylus orientation. Defaults: identity (scripted devices work in world mm).
  Eigen::Vector3d deviceOffsetMm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d deviceRotation = Eigen::Matrix3d::Identity();
  double deviceScale = 1.0;
  int overrunLimit =
      5; ///< pause when more than this many of the last overrunWindow frames overran; < 0 = never
  int overrunWindow = 100; ///< frames
  /// Frames after a resume whose overruns do not count toward the pause rule (they still count in
  /// the timing statistics); the window itself starts empty. Default 200 (0.2 s at 1 kHz).
  int resumeWarmupFrames = 200;
  /// Frames after Start() whose overruns do not count toward the pause rule (they still count in
  /// the timing statistics): the first frames pay for the thread's start, cold caches and the
  /// view's first full surface extraction. Default 200 (0.2 s at 1 kHz); 0 = none.
  int startWarmupFrames = 200;
  /// After a resume, the proxy's target moves toward the device at most this fast, world mm/s
  /// (default 20); once it reaches the device it follows it directly again. <= 0: no limit.
  double catchUpSpeedMmPerS = 20;
  /// Runaway: pause when the device is further than this from the proxy, device mm (default 50,
  /// six times the Touch coupling's 8 mm stretch at full force); <= 0: never.
  double runawayDistanceMm = 50;
  /// Runaway: pause when the proxy leaves the bone's bounding box grown by this margin, world mm
  /// (default 150); <= 0: never.
  double runawayMarginMm = 150;
  bool realTime = true;   ///< false: frames back to back (no sleeping; tests and replay)
  int64_t maxFrames = -1; ///< pause (reason Finished) after this many frames; < 0 = no limit
  bool record = true;     ///< push a FrameRecord per frame into the ring
  size_t recordCapacity = 1 << 16; ///< ring size, records
};

struct SessionSnapshot {
  SessionState state = SessionState::Idle;
  PauseReason pauseReason = PauseReason::None;
  int64_t frame = 0;                                          ///< frames run
  double timeS = 0;                                           ///< session time, s
  Eigen::Vector3d devicePositionMm = Eigen::Vector3d::Zero(); ///< world mm
  Eigen::Matrix3d toolRotation = Eigen::Matrix3d::Identity(); ///< tool -> world
  Eigen::Vector3d proxyPositionMm = Eigen::Vector3d::Zero();  ///< world mm
  Eigen::Vector3d deviceForceN = Eigen::Vector3d::Zero();     ///< last force sent, world N
  double thrustN = 0, torqueNmm = 0, feedMmPerRev = 0;
  double removedVolumeMm3 = 0; ///< since Start
  int64_t removedVoxels = 0;   ///< since Start
  double maxDeviceForceN = 0;  ///< largest |force| sent so far, N
  TimingStats timing;          ///< refreshed every 64 frames and at every pause
  uint64_t droppedRecords = 0;
};

class HapticSession {
public:
  /// setup and device must outlive the session. Builds the proxy (throws on bad options).
  HapticSession(MachiningSetup& setup, std::shared_ptr<Device> device,
                const SessionOptions& o = {});
  ~HapticSession();
  HapticSession(const HapticSession&) = delete;
  HapticSession& operator=(const HapticSession&) = delete;

  /// Replaces the device; only while not running (throws std::logic_error otherwise). The proxy is
  /// rebuilt for the new device's limits.
  void SetDevice(std::shared_ptr<Device> device);
  /// Opens the device and starts the haptic thread. Throws if the device fails to start or the
  /// session already ran.
  void Start();
  void Pause();
  /// Resumes a paused session. Returns false, and the session stays paused, after a device error.
  bool Resume();
  /// Stops and joins the thread, zero force, closes the device. Idempotent.
  void Stop();
  /// Spindle speed from now on, rpm (0 = stopped). Any thread.
  void SetSpindleSpeed(double rpm) { SpeedRpm_.store(rpm); }
  double SpindleSpeed() const { return SpeedRpm_.load(); }
  /// Blocks the caller (not the haptic thread) until the session pauses or stops, or timeoutS
  /// passes; returns whether it paused/stopped.
  bool WaitUntilPaused(double timeoutS) const;
  /// Latest published state; any thread, never delays the haptic thread.
  SessionSnapshot Snapshot() const;
  /// Moves the records so far into `out`; one consumer thread at a time.
  size_t DrainRecords(std::vector<FrameRecord>& out) { return Ring_.Drain(out); }
  /// Exact timing over all frames; valid after Stop() (before: the last snapshot's).
  TimingStats Timing() const;
  const SessionOptions& Options() const { return O_; }
  const VirtualCoupling& Coupling() const { return Proxy_->Coupling(); }
  Device& GetDevice() { return *Device_; }

private:
  void Loop();
  void RunFrame();
  void Fault(PauseReason why);
  /// Haptic thread: try-lock (never waits), returns false when the slot was busy. wait = true
  /// (other threads, outside the loop): blocks for the slot.
  bool Publish(bool wait = false);

  MachiningSetup& Setup_;
  std::shared_ptr<Device> Device_;
  SessionOptions O_;
  double Period_;
  std::unique_ptr<Proxy> Proxy_;
  std::thread Thread_;
  std::atomic<bool> StopFlag_{false}, PauseFlag_{false}, Started_{false};
  std::atomic<int> State_{int(SessionState::Idle)};
  std::atomic<int> Reason_{int(PauseReason::None)};
  std::atomic<double> SpeedRpm_{0};
  RecordRing Ring_;
  // Haptic-thread state.
  SessionSnapshot Work_;
  TimingHistogram Hist_;
  std::vector<uint8_t> OverrunWindow_;
  int OverrunsInWindow_ = 0;
  int WarmupLeft_ = 0;                               // frames before overruns count again
  bool CatchingUp_ = false;                          // the target is still on its way to the device
  Eigen::Vector3d Target_ = Eigen::Vector3d::Zero(); // world mm, what the proxy followed
  std::atomic<bool> DeviceFailed_{false};            // a device error: zero force from now on
  Eigen::Vector3d BoneLo_, BoneHi_;                  // the bone's world box, mm
  bool WasPaused_ = false, Resumed_ = false, Unpublished_ = false;
  DevicePose Pose_;
  // Double-buffered snapshot.
  mutable std::mutex SlotMutex_[2];
  SessionSnapshot Slot_[2];
  std::atomic<int> Latest_{0};
  std::atomic<uint64_t> SkippedSnapshots_{0};
};

} // namespace bm
