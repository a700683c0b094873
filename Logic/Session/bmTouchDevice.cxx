#include "bmTouchDevice.h"

#include "bmHapticDeviceModel.h"

#include <dlfcn.h>

#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "bmSharedLibraryCheck.h"

namespace bm {

const char* hd::ErrorName(HDerror code) {
  switch (code) {
  case kSuccess:
    return "HD_SUCCESS";
  case kInvalidEnum:
    return "HD_INVALID_ENUM";
  case kInvalidValue:
    return "HD_INVALID_VALUE";
  case kInvalidOperation:
    return "HD_INVALID_OPERATION";
  case kInvalidInputType:
    return "HD_INVALID_INPUT_TYPE";
  case kBadHandle:
    return "HD_BAD_HANDLE";
  case kWarmMotors:
    return "HD_WARM_MOTORS";
  case kExceededMaxForce:
    return "HD_EXCEEDED_MAX_FORCE";
  case kExceededMaxForceImpulse:
    return "HD_EXCEEDED_MAX_FORCE_IMPULSE";
  case kExceededMaxVelocity:
    return "HD_EXCEEDED_MAX_VELOCITY";
  case kForceError:
    return "HD_FORCE_ERROR";
  case kDeviceFault:
    return "HD_DEVICE_FAULT";
  case kDeviceAlreadyInitiated:
    return "HD_DEVICE_ALREADY_INITIATED";
  case kCommError:
    return "HD_COMM_ERROR";
  case kCommConfigError:
    return "HD_COMM_CONFIG_ERROR";
  case kTimerError:
    return "HD_TIMER_ERROR";
  case kIllegalBegin:
    return "HD_ILLEGAL_BEGIN";
  case kIllegalEnd:
    return "HD_ILLEGAL_END";
  case kFrameError:
    return "HD_FRAME_ERROR";
  case kInvalidPriority:
    return "HD_INVALID_PRIORITY";
  case kSchedulerFull:
    return "HD_SCHEDULER_FULL";
  case kInvalidLicense:
    return "HD_INVALID_LICENSE";
  case kNonFinitePose:
    return "non-finite pose from the device";
  default:
    return "HD error";
  }
}

struct TouchDevice::Api {
  HHD (*initDevice)(HDstring);
  void (*disableDevice)(HHD);
  void (*makeCurrentDevice)(HHD);
  void (*beginFrame)(HHD);
  void (*endFrame)(HHD);
  void (*enable)(HDenum);
  void (*getDoublev)(HDenum, HDdouble*);
  void (*getIntegerv)(HDenum, HDint*);
  void (*setDoublev)(HDenum, const HDdouble*);
  HDErrorInfo (*getError)();
  HDSchedulerHandle (*scheduleAsynchronous)(HDSchedulerCallback, void*, HDushort);
  void (*unschedule)(HDSchedulerHandle);
  void (*startScheduler)();
  void (*stopScheduler)();
  HDstring (*getString)(HDenum) = nullptr; // optional
};

namespace {
template <class F> void Bind(void* lib, const char* name, F& fn, const std::string& path) {
  fn = reinterpret_cast<F>(BindLibraryFunction(lib, name, path));
}

// An hdInitDevice call on its own thread, so that a library that never returns from it cannot
// hang Start(): the thread is abandoned at the timeout (and the library left loaded, since the
// call may still be inside it); should the call return later, the device it opened is disabled.
struct InitCall {
  std::mutex m;
  std::condition_variable done;
  bool returned = false, abandoned = false;
  HHD handle = hd::kInvalidHandle;
  HDErrorInfo error{hd::kSuccess, 0, 0};
};
} // namespace

TouchDevice::TouchDevice(std::string libraryPath, double stallTimeoutS, double initTimeoutS)
    : Path_(std::move(libraryPath)), StallTimeoutS_(stallTimeoutS), InitTimeoutS_(initTimeoutS) {
  if (!std::isfinite(stallTimeoutS) || stallTimeoutS <= 0)
    throw std::invalid_argument("touch: stall timeout " + std::to_string(stallTimeoutS) +
                                " s must be finite and > 0");
  if (!std::isfinite(initTimeoutS) || initTimeoutS <= 0 || initTimeoutS > 600)
    throw std::invalid_argument("touch: hdInitDevice timeout " + std::to_string(initTimeoutS) +
                                " s is outside (0, 600] s");
  if (Path_.empty()) {
    const char* env = std::getenv("BM_LIBHD");
    Path_ = env && *env ? env : "libHD.so";
  }
}

TouchDevice::~TouchDevice() {
  Stop();
}

void TouchDevice::Start() {
  if (Running_)
    return;
  // A truncated or foreign file would fault inside dlopen (SIGBUS): check its headers first.
  if (const std::string file = FindSharedLibrary(Path_); !file.empty()) {
    try {
      CheckSharedLibraryFile(file);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string("touch: ") + e.what());
    }
  }
  Lib_ = dlopen(Path_.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!Lib_)
    throw std::runtime_error("touch: cannot load '" + Path_ + "': " + dlerror());
  Api_ = new Api{};
  try {
    try {
      for (const char* symbol : hd::kRequiredSymbols) // every one, before any is called
        BindLibraryFunction(Lib_, symbol, Path_);
      if (dlsym(Lib_, hd::kVersionSymbol))
        Bind(Lib_, hd::kVersionSymbol, Api_->getString, Path_);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string("touch: ") + e.what());
    }
    Bind(Lib_, "hdInitDevice", Api_->initDevice, Path_);
    Bind(Lib_, "hdDisableDevice", Api_->disableDevice, Path_);
    Bind(Lib_, "hdMakeCurrentDevice", Api_->makeCurrentDevice, Path_);
    Bind(Lib_, "hdBeginFrame", Api_->beginFrame, Path_);
    Bind(Lib_, "hdEndFrame", Api_->endFrame, Path_);
    Bind(Lib_, "hdEnable", Api_->enable, Path_);
    Bind(Lib_, "hdGetDoublev", Api_->getDoublev, Path_);
    Bind(Lib_, "hdGetIntegerv", Api_->getIntegerv, Path_);
    Bind(Lib_, "hdSetDoublev", Api_->setDoublev, Path_);
    Bind(Lib_, "hdGetError", Api_->getError, Path_);
    Bind(Lib_, "hdScheduleAsynchronous", Api_->scheduleAsynchronous, Path_);
    Bind(Lib_, "hdUnschedule", Api_->unschedule, Path_);
    Bind(Lib_, "hdStartScheduler", Api_->startScheduler, Path_);
    Bind(Lib_, "hdStopScheduler", Api_->stopScheduler, Path_);
    auto check = [&](const char* step) {
      const HDErrorInfo e = Api_->getError();
      if (e.errorCode != hd::kSuccess)
        throw std::runtime_error(std::string("touch: ") + step +
                                 " failed: " + hd::ErrorName(e.errorCode) + " (device code " +
                                 std::to_string(e.internalErrorCode) + ")");
    };
    InitDevice();
    if (Handle_ == hd::kInvalidHandle)
      throw std::runtime_error("touch: hdInitDevice returned no device");
    Api_->makeCurrentDevice(Handle_);
    if (Api_->getString) {
      const char* version = Api_->getString(hd::kVersion);
      if (version && *version >= '0' && *version <= '9' &&
          std::atoi(version) < hd::kMinimumMajorVersion)
        throw std::runtime_error("touch: '" + Path_ + "' is HD API version " +
                                 std::string(version).substr(0, 40) + ", older than " +
                                 std::to_string(hd::kMinimumMajorVersion) +
                                 " (OpenHaptics 3 drives the Touch)");
      check("hdGetString(HD_VERSION)");
      const char* model = Api_->getString(hd::kDeviceModelType);
      Model_ = model ? std::string(model).substr(0, 80) : "";
      Api_->getError(); // a library without the model's name: the Touch's limits apply
    }
    Api_->enable(hd::kForceOutput);
    check("hdEnable(HD_FORCE_OUTPUT)");
    HDdouble v = 0;
    Api_->getDoublev(hd::kNominalMaxForce, &v);
    if (std::isfinite(v) && v > 0)
      Limits_.maxForceN = v;
    v = 0;
    Api_->getDoublev(hd::kNominalMaxStiffness, &v);
    if (std::isfinite(v) && v > 0)
      Limits_.maxStiffnessNPerMm = v;
    v = 0;
    Api_->getDoublev(hd::kNominalMaxDamping, &v);
    if (std::isfinite(v) && v > 0)
      Limits_.maxDampingNsPerMm = v;
    HDint rate = 0;
    Api_->getIntegerv(hd::kUpdateRate, &rate);
    if (rate > 0)
      Limits_.rateHz = rate;
    check("querying the nominal limits");
    // Never more than the model's own peak force, whatever the driver claims.
    Limits_ = CapToModel(Limits_, Model_);
    Callback_ = Api_->scheduleAsynchronous(&TouchDevice::Servo, this, hd::kMaxSchedulerPriority);
    check("hdScheduleAsynchronous");
    Scheduled_ = true;
    Api_->startScheduler();
    check("hdStartScheduler");
    Running_ = true;
    // Wait for the servo loop's first sample, so that Read() never hands out a pose the device
    // has not measured (the default pose is the workspace origin, far from the stylus).
    const auto started = std::chrono::steady_clock::now();
    while (Ticks_.load() == 0) {
      if (Error_.load() != hd::kSuccess)
        throw std::runtime_error(std::string("touch: the first servo frame failed: ") +
                                 LastError());
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() >
          kFirstSampleTimeoutS)
        throw std::runtime_error("touch: the servo loop delivered no sample within " +
                                 std::to_string(kFirstSampleTimeoutS) + " s of hdStartScheduler");
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    State_.GetPose(Last_, LastSample_);
    LastFresh_ = std::chrono::steady_clock::now();
  } catch (...) {
    Close();
    throw;
  }
}

void TouchDevice::InitDevice() {
  auto call = std::make_shared<InitCall>();
  auto init = Api_->initDevice;
  auto disable = Api_->disableDevice;
  auto getError = Api_->getError;
  std::thread([call, init, disable, getError] {
    const HHD handle = init(nullptr); // HD_DEFAULT_DEVICE
    const HDErrorInfo error = getError();
    std::lock_guard<std::mutex> lock(call->m);
    call->returned = true;
    call->handle = handle;
    call->error = error;
    if (call->abandoned && handle != hd::kInvalidHandle)
      disable(handle);
    call->done.notify_all();
  }).detach();
  std::unique_lock<std::mutex> lock(call->m);
  if (!call->done.wait_for(lock, std::chrono::duration<double>(InitTimeoutS_),
                           [&] { return call->returned; })) {
    call->abandoned = true;
    Lib_ = nullptr; // left loaded: the abandoned call may still be running inside it
    std::ostringstream s;
    s << "touch: hdInitDevice did not return within " << InitTimeoutS_ << " s ('" << Path_
      << "'); the device was not opened";
    throw std::runtime_error(s.str());
  }
  Handle_ = call->handle;
  if (call->error.errorCode != hd::kSuccess) {
    const HDErrorInfo e = call->error;
    if (Handle_ != hd::kInvalidHandle)
      Api_->disableDevice(Handle_);
    Handle_ = hd::kInvalidHandle;
    throw std::runtime_error(std::string("touch: hdInitDevice failed: ") +
                             hd::ErrorName(e.errorCode) + " (device code " +
                             std::to_string(e.internalErrorCode) + ")");
  }
}

HDCallbackCode TouchDevice::Servo(void* self) {
  return static_cast<TouchDevice*>(self)->ServoTick();
}

HDCallbackCode TouchDevice::ServoTick() {
  Api_->beginFrame(Handle_);
  HDdouble pos[3] = {0, 0, 0}, m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  HDint buttons = 0;
  Api_->getDoublev(hd::kCurrentPosition, pos);
  Api_->getDoublev(hd::kCurrentTransform, m);
  Api_->getIntegerv(hd::kCurrentButtons, &buttons);
  bool finite = std::isfinite(pos[0]) && std::isfinite(pos[1]) && std::isfinite(pos[2]);
  for (double x : m)
    finite = finite && std::isfinite(x);
  if (!finite) {
    HDerror none = hd::kSuccess;
    Error_.compare_exchange_strong(none, hd::kNonFinitePose);
  }
  // After any error (latched in an earlier tick, or a bad pose now) the motors get zero in this
  // same tick, whatever the session last wrote.
  Eigen::Vector3d f = Error_.load(std::memory_order_relaxed) == hd::kSuccess
                          ? State_.GetForce()
                          : Eigen::Vector3d::Zero();
  // The last guard: finite and within the (model-capped) limit, whatever was written.
  if (!f.allFinite())
    f.setZero();
  else if (f.norm() > Limits_.maxForceN)
    f *= Limits_.maxForceN / f.norm() * (1.0 - 1e-12);
  const HDdouble force[3] = {f(0), f(1), f(2)};
  Api_->setDoublev(hd::kCurrentForce, force);
  Api_->endFrame(Handle_);
  const HDErrorInfo e = Api_->getError();
  if (e.errorCode != hd::kSuccess) {
    InternalError_.store(e.internalErrorCode, std::memory_order_relaxed);
    HDerror none = hd::kSuccess;
    Error_.compare_exchange_strong(none, e.errorCode); // latch the first error
  }
  if (!finite) {
    Ticks_.fetch_add(1, std::memory_order_relaxed);
    return hd::kCallbackContinue; // the session sees the latched error, never the bad pose
  }
  DevicePose p;
  p.positionMm = {pos[0], pos[1], pos[2]};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      p.rotation(r, c) = m[4 * c + r]; // column-major
  p.buttons = uint32_t(buttons);
  State_.PutPose(p);
  Ticks_.fetch_add(1, std::memory_order_relaxed);
  return hd::kCallbackContinue;
}

DeviceStatus TouchDevice::Read(DevicePose& pose) {
  if (!Running_)
    return DeviceStatus::NoResponse;
  if (Error_.load(std::memory_order_relaxed) != hd::kSuccess)
    return DeviceStatus::Error;
  uint64_t sample = LastSample_;
  State_.TryGetPose(Last_, sample);
  const auto now = std::chrono::steady_clock::now();
  if (sample != LastSample_) {
    LastSample_ = sample;
    LastFresh_ = now;
  } else if (std::chrono::duration<double>(now - LastFresh_).count() > StallTimeoutS_) {
    return DeviceStatus::NoResponse;
  }
  pose = Last_;
  return DeviceStatus::Ok;
}

DeviceStatus TouchDevice::Write(const Eigen::Vector3d& forceN) {
  if (!Running_)
    return DeviceStatus::NoResponse;
  // Busy only while the servo copies the force out: a lost write lands next frame. Zero force
  // (a pause or a fault) must get through now, so it waits for those few instructions.
  if (forceN.isZero(0.0))
    State_.PutForce(forceN);
  else
    State_.TryPutForce(forceN);
  return Error_.load(std::memory_order_relaxed) != hd::kSuccess ? DeviceStatus::Error
                                                                : DeviceStatus::Ok;
}

std::string TouchDevice::LastError() const {
  const HDerror e = Error_.load(std::memory_order_relaxed);
  if (e == hd::kSuccess)
    return {};
  return std::string(hd::ErrorName(e)) + " (device code " + std::to_string(InternalError_.load()) +
         ")";
}

void TouchDevice::Stop() {
  if (Running_) {
    // Zero force, then let one servo tick send it (at most ~20 ms) before the scheduler stops.
    State_.PutForce(Eigen::Vector3d::Zero());
    const uint64_t t0 = Ticks_.load();
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
    while (Ticks_.load() < t0 + 2 && std::chrono::steady_clock::now() < until)
      std::this_thread::yield();
  }
  Close();
}

void TouchDevice::Close() {
  if (Api_) {
    if (Running_)
      Api_->stopScheduler(); // joins the servo thread: no callback runs after this
    if (Scheduled_)
      Api_->unschedule(Callback_);
    if (Handle_ != hd::kInvalidHandle)
      Api_->disableDevice(Handle_);
  }
  Running_ = Scheduled_ = false;
  Handle_ = hd::kInvalidHandle;
  delete Api_;
  Api_ = nullptr;
  if (Lib_)
    dlclose(Lib_);
  Lib_ = nullptr;
}

} // namespace bm
