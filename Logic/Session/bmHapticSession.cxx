#include "bmHapticSession.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#endif

namespace bm {

const char* ToString(SessionState s) {
  switch (s) {
  case SessionState::Idle:
    return "idle";
  case SessionState::Running:
    return "running";
  case SessionState::Paused:
    return "paused";
  case SessionState::Stopped:
    return "stopped";
  }
  return "?";
}

const char* ToString(PauseReason r) {
  switch (r) {
  case PauseReason::None:
    return "none";
  case PauseReason::User:
    return "user";
  case PauseReason::Finished:
    return "finished";
  case PauseReason::Overrun:
    return "overrun";
  case PauseReason::DeviceError:
    return "device error";
  case PauseReason::DeviceSilent:
    return "device not answering";
  case PauseReason::FrameError:
    return "frame error";
  case PauseReason::Runaway:
    return "runaway";
  }
  return "?";
}

HapticSession::HapticSession(MachiningSetup& setup, std::shared_ptr<Device> device,
                             const SessionOptions& o)
    : Setup_(setup), Device_(std::move(device)), O_(o), Ring_(o.recordCapacity) {
  if (!Device_)
    throw std::invalid_argument("session: no device");
  if (!(O_.rateHz > 0))
    throw std::invalid_argument("session: rate must be > 0 Hz");
  Period_ = 1.0 / O_.rateHz;
  SpeedRpm_.store(O_.speedRpm >= 0 ? O_.speedRpm : setup.GetScene().trial.speedRpm);
  Proxy_ = std::make_unique<Proxy>(Setup_, Device_->Limits(), Period_, O_.proxy);
  OverrunWindow_.assign(size_t(std::max(1, O_.overrunWindow)), 0);
  const Voxmap& bone = setup.Bone();
  const auto d = bone.Dims();
  const auto lo = bone.GridToWorld({0.0, 0.0, 0.0});
  const auto hi = bone.GridToWorld({double(d[0] - 1), double(d[1] - 1), double(d[2] - 1)});
  BoneLo_ = Eigen::Vector3d(lo[0], lo[1], lo[2]).cwiseMin(Eigen::Vector3d(hi[0], hi[1], hi[2]));
  BoneHi_ = Eigen::Vector3d(lo[0], lo[1], lo[2]).cwiseMax(Eigen::Vector3d(hi[0], hi[1], hi[2]));
  Publish(true);
}

HapticSession::~HapticSession() {
  Stop();
}

void HapticSession::SetDevice(std::shared_ptr<Device> device) {
  if (State_.load() == int(SessionState::Running) || State_.load() == int(SessionState::Paused))
    throw std::logic_error(
        "session: the device can only be changed while the session is not running");
  if (!device)
    throw std::invalid_argument("session: no device");
  Device_ = std::move(device);
  Proxy_ = std::make_unique<Proxy>(Setup_, Device_->Limits(), Period_, O_.proxy);
}

void HapticSession::Start() {
  if (Started_.exchange(true))
    throw std::logic_error("session: already started");
  Device_->Start();
  // Limits are known now (the Touch reads them from the driver): rebuild the proxy if they differ.
  const DeviceLimits l = Device_->Limits();
  const VirtualCoupling expect(O_.proxy.coupling, l, Period_);
  if (expect.Stiffness() != Proxy_->Coupling().Stiffness() ||
      expect.Damping() != Proxy_->Coupling().Damping() ||
      expect.MaxForce() != Proxy_->Coupling().MaxForce())
    Proxy_ = std::make_unique<Proxy>(Setup_, l, Period_, O_.proxy);
  Proxy_->Prepare(SpeedRpm_.load());
  WarmupLeft_ = std::max(0, O_.startWarmupFrames); // before the thread: it reads it first
  State_.store(int(SessionState::Running));
  Work_.state = SessionState::Running;
  Publish(true);
  Thread_ = std::thread([this] { Loop(); });
}

void HapticSession::Pause() {
  Reason_.store(int(PauseReason::User));
  PauseFlag_.store(true);
}

bool HapticSession::Resume() {
  if (DeviceFailed_.load())
    return false;
  Reason_.store(int(PauseReason::None));
  PauseFlag_.store(false);
  return true;
}

void HapticSession::Stop() {
  StopFlag_.store(true);
  if (Thread_.joinable())
    Thread_.join();
  if (Started_.load() && State_.load() != int(SessionState::Stopped)) {
    Device_->Write(Eigen::Vector3d::Zero());
    Device_->Stop();
    State_.store(int(SessionState::Stopped));
    Work_.state = SessionState::Stopped;
    Work_.timing = Hist_.Stats();
    Publish(true);
  }
}

bool HapticSession::WaitUntilPaused(double timeoutS) const {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  while (std::chrono::steady_clock::now() < until) {
    const int s = State_.load();
    if (s == int(SessionState::Paused) || s == int(SessionState::Stopped))
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

SessionSnapshot HapticSession::Snapshot() const {
  const int i = Latest_.load(std::memory_order_acquire);
  std::lock_guard<std::mutex> lock(SlotMutex_[i]);
  return Slot_[i];
}

TimingStats HapticSession::Timing() const {
  if (State_.load() == int(SessionState::Stopped))
    return Hist_.Stats(); // the thread has been joined
  return Snapshot().timing;
}

bool HapticSession::Publish(bool wait) {
  const int w = 1 - Latest_.load(std::memory_order_relaxed);
  std::unique_lock<std::mutex> lock(SlotMutex_[w], std::defer_lock);
  if (wait) {
    lock.lock();
  } else if (!lock.try_lock()) {
    SkippedSnapshots_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  Work_.droppedRecords = Ring_.Dropped();
  Slot_[w] = Work_;
  lock.unlock();
  Latest_.store(w, std::memory_order_release);
  return true;
}

void HapticSession::Fault(PauseReason why) {
  // Zero force within this frame; the proxy and the cut stay as they are.
  if (why == PauseReason::DeviceError)
    DeviceFailed_.store(true);
  Device_->Write(Eigen::Vector3d::Zero());
  Work_.deviceForceN.setZero();
  Reason_.store(int(why));
  PauseFlag_.store(true);
}

namespace {
/// Asks for real-time scheduling (SCHED_FIFO, priority 10 of 1..99) for the calling thread, as
/// haptic servo loops run: at the ordinary priority a thread of a 1 kHz loop waits for the
/// time slices of every other runnable thread, and a frame of 0.2 ms took 4 to 23 ms in the
/// ParaView dock on 2 busy cores (load 2-4), enough for the overrun pause while the tool was in
/// the air. The loop sleeps most of each period and Linux keeps 5 % of every second for the other
/// threads. Without the permission (CAP_SYS_NICE or RLIMIT_RTPRIO) the thread stays as it was.
void RequestRealTimeScheduling() {
#ifdef __linux__
  sched_param param{};
  param.sched_priority = 10;
  pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); // EPERM: stays at the ordinary one
#endif
}
} // namespace

void HapticSession::Loop() {
  using clock = std::chrono::steady_clock;
  if (O_.realTime)
    RequestRealTimeScheduling(); // frames back to back (tests, replay) keep the ordinary priority
  const auto period =
      std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(Period_));
  auto next = clock::now();
  while (!StopFlag_.load(std::memory_order_acquire)) {
    if (PauseFlag_.load(std::memory_order_acquire)) {
      if (!WasPaused_) {
        Device_->Write(Eigen::Vector3d::Zero());
        WasPaused_ = true;
        Work_.state = SessionState::Paused;
        Work_.pauseReason = PauseReason(Reason_.load());
        Work_.deviceForceN.setZero();
        Work_.timing = Hist_.Stats();
        Unpublished_ = true;
      }
      if (Unpublished_ && Publish()) {
        // The state flag follows the published snapshot (a reader may have held the slot), so
        // whoever sees Paused also reads the paused snapshot.
        Unpublished_ = false;
        State_.store(int(SessionState::Paused));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      next = clock::now();
      continue;
    }
    if (WasPaused_) {
      WasPaused_ = false;
      Proxy_->ForgetDeviceMotion();
      Resumed_ = true;
      // Re-arm the overrun rule: an empty window, and a warm-up whose overruns do not count.
      std::fill(OverrunWindow_.begin(), OverrunWindow_.end(), uint8_t(0));
      OverrunsInWindow_ = 0;
      WarmupLeft_ = std::max(0, O_.resumeWarmupFrames);
      // The proxy follows a device that moved while paused from where the proxy is.
      Target_ = Proxy_->Position();
      CatchingUp_ = O_.catchUpSpeedMmPerS > 0;
      Work_.state = SessionState::Running;
      Work_.pauseReason = PauseReason::None;
      State_.store(int(SessionState::Running));
    }
    RunFrame();
    if (O_.maxFrames >= 0 && Work_.frame >= O_.maxFrames && !PauseFlag_.load()) {
      Reason_.store(int(PauseReason::Finished));
      PauseFlag_.store(true);
    }
    if (O_.realTime) {
      next += period;
      const auto now = clock::now();
      if (now > next + period)
        next = now; // fell behind: do not try to catch up with a burst
      std::this_thread::sleep_until(next);
    }
  }
}

void HapticSession::RunFrame() {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const double t = double(Work_.frame) * Period_;
  Device_->Advance(t, Period_);
  const DeviceStatus st = Device_->Read(Pose_);
  if (st != DeviceStatus::Ok) {
    Fault(st == DeviceStatus::Error ? PauseReason::DeviceError : PauseReason::DeviceSilent);
    return;
  }
  if (!Pose_.positionMm.allFinite() || !Pose_.rotation.allFinite()) {
    Fault(PauseReason::DeviceError); // a non-finite pose is a device fault: zero force now
    return;
  }
  const Eigen::Vector3d device =
      O_.deviceOffsetMm + O_.deviceScale * (O_.deviceRotation * Pose_.positionMm);
  // After a resume the target walks to the device at a bounded speed; then it is the device.
  Eigen::Vector3d xd = device;
  if (CatchingUp_) {
    const double step = O_.catchUpSpeedMmPerS * Period_;
    const Eigen::Vector3d gap = device - Target_;
    const double n = gap.norm();
    if (n <= step) {
      CatchingUp_ = false;
    } else {
      Target_ += gap * (step / n);
      xd = Target_;
    }
  }
  // The orientation goes through the recorded quaternion, so a replay sees bit-identical input.
  const Eigen::Quaterniond q = Eigen::Quaterniond(O_.deviceRotation * Pose_.rotation).normalized();
  const Eigen::Matrix3d R = ToolRotationFromQuaternion({q.w(), q.x(), q.y(), q.z()});
  const double speed = SpeedRpm_.load(std::memory_order_relaxed);
  ProxyFrame pf;
  try {
    pf = Proxy_->Step(xd, R, speed);
  } catch (const std::exception&) {
    Fault(PauseReason::FrameError);
    return;
  }
  // World force back to the device frame; the final guard: finite and within the limit, and
  // nothing after a device error.
  const Eigen::Vector3d fDev =
      DeviceFailed_.load(std::memory_order_relaxed)
          ? Eigen::Vector3d::Zero()
          : VirtualCoupling::Clamp(O_.deviceRotation.transpose() * pf.deviceForceN,
                                   Device_->Limits().maxForceN);
  const DeviceStatus ws = Device_->Write(fDev);
  const double ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
  const bool overrun = ms > Period_ * 1000.0;
  Hist_.Add(ms, overrun);
  uint8_t& slot = OverrunWindow_[size_t(Work_.frame % int64_t(OverrunWindow_.size()))];
  const bool counts = overrun && WarmupLeft_ == 0;
  OverrunsInWindow_ += int(counts) - int(slot);
  slot = counts;
  if (WarmupLeft_ > 0)
    --WarmupLeft_;

  Work_.frame += 1;
  Work_.timeS = double(Work_.frame) * Period_;
  Work_.devicePositionMm = device;
  Work_.toolRotation = R;
  Work_.proxyPositionMm = pf.proxyPositionMm;
  Work_.deviceForceN = O_.deviceRotation * fDev;
  Work_.thrustN = pf.thrustN;
  Work_.torqueNmm = pf.torqueNmm;
  Work_.feedMmPerRev = pf.feedMmPerRev;
  Work_.removedVolumeMm3 += pf.removedVolumeMm3;
  Work_.removedVoxels += pf.removedVoxels;
  Work_.maxDeviceForceN = std::max(Work_.maxDeviceForceN, fDev.norm());
  if (O_.record) {
    FrameRecord r;
    r.frame = Work_.frame - 1;
    r.timeS = t;
    r.devicePos = {xd(0), xd(1), xd(2)};
    r.deviceQuat = {q.w(), q.x(), q.y(), q.z()};
    r.proxyPos = {pf.proxyPositionMm(0), pf.proxyPositionMm(1), pf.proxyPositionMm(2)};
    r.feedMmPerRev = pf.feedMmPerRev;
    r.thrustN = pf.thrustN;
    r.torqueNmm = pf.torqueNmm;
    r.couplingForce = {pf.couplingForceN(0), pf.couplingForceN(1), pf.couplingForceN(2)};
    const Eigen::Vector3d fw = O_.deviceRotation * fDev;
    r.deviceForce = {fw(0), fw(1), fw(2)};
    r.frameMs = ms;
    r.removedVoxels = pf.removedVoxels;
    r.removedVolumeMm3 = pf.removedVolumeMm3;
    r.speedRpm = speed;
    r.buttons = Pose_.buttons;
    r.flags = Resumed_ ? FrameRecord::kResumed : 0u;
    Ring_.Push(r);
  }
  Resumed_ = false;
  if ((Work_.frame & 63) == 0)
    Work_.timing = Hist_.Stats();
  Unpublished_ = !Publish();
  const double scale = std::abs(O_.deviceScale) > 0 ? std::abs(O_.deviceScale) : 1.0;
  const bool farFromProxy =
      O_.runawayDistanceMm > 0 && (xd - pf.proxyPositionMm).norm() / scale > O_.runawayDistanceMm;
  const bool outOfRegion =
      O_.runawayMarginMm > 0 && ((pf.proxyPositionMm - BoneLo_).minCoeff() < -O_.runawayMarginMm ||
                                 (BoneHi_ - pf.proxyPositionMm).minCoeff() < -O_.runawayMarginMm);
  if (ws != DeviceStatus::Ok)
    Fault(ws == DeviceStatus::Error ? PauseReason::DeviceError : PauseReason::DeviceSilent);
  else if (farFromProxy || outOfRegion)
    Fault(PauseReason::Runaway);
  else if (O_.overrunLimit >= 0 && OverrunsInWindow_ > O_.overrunLimit)
    Fault(PauseReason::Overrun);
}

} // namespace bm
