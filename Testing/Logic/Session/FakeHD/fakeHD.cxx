// fakeHD.cxx - a test double of OpenHaptics' libHD.so: the HD API functions the Touch device
// binds (bmHDApi.h), plus fakeHD_* controls for the tests. A scheduler thread calls the scheduled
// callbacks at 1 kHz; forces written with hdSetDoublev(HD_CURRENT_FORCE) are logged; a force above
// the nominal maximum raises HD_EXCEEDED_MAX_FORCE as the real device does; errors can be injected
// and the servo loop stalled. fakeHD_SetFault makes hdInitDevice crash (SIGSEGV) or hang, or the
// library report an HD API version too old, or enable or the servo callback fault; a process
// that loads it (bmsim) takes its fault from FAKEHD_FAULT. Built a second time with
// FAKEHD_WITHOUT_END_FRAME (libHDnoEndFrame.so): a library that lacks one entry point.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <mutex>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "bmHDApi.h"

namespace {
struct Fake {
  std::mutex m;
  std::array<double, 3> position{0, 0, 0};
  int buttons = 0;
  bool forceOutput = false;
  bool initialised = false;
  std::vector<std::array<double, 3>> forces;
  std::deque<HDErrorInfo> errors;
  std::vector<std::pair<HDSchedulerCallback, void*>> callbacks;
  std::thread scheduler;
  std::atomic<bool> running{false}, stalled{false};
  std::atomic<long> ticks{0};
  double maxForce = 3.3, maxStiffness = 0.35, maxDamping = 0.003;
  int initError = 0;
  std::atomic<int> fault{0}; // fakeHD_SetFault's mode
};
// Made on first use and deleted by the unload hook below, which reads it last (a function-local
// static object could be destroyed before that hook runs).
Fake*& FakeState() {
  static Fake* f = new Fake;
  return f;
}
Fake& F() {
  return *FakeState();
}
void PushError(HDerror code, int internal) {
  F().errors.push_back(HDErrorInfo{code, internal, 1});
}
} // namespace

extern "C" {
HHD hdInitDevice(HDstring) {
  if (F().fault.load() == 1)
    std::raise(SIGSEGV);        // what a faulting driver does to its process
  while (F().fault.load() == 2) // a driver that never returns, until the test lets it
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::lock_guard<std::mutex> l(F().m);
  if (F().initError) {
    PushError(HDerror(F().initError), 42);
    return bm::hd::kInvalidHandle;
  }
  F().initialised = true;
  return 1;
}
void hdDisableDevice(HHD) {
  std::lock_guard<std::mutex> l(F().m);
  F().initialised = false;
  F().forceOutput = false;
}
void hdMakeCurrentDevice(HHD) {}
void hdBeginFrame(HHD) {
  if (F().fault.load() == 5)
    std::raise(SIGSEGV); // a driver that faults in the servo callback
}
#ifndef FAKEHD_WITHOUT_END_FRAME
void hdEndFrame(HHD) {}
#endif
HDstring hdGetString(HDenum p) {
  if (p == bm::hd::kVersion)
    return F().fault.load() == 3 ? "2.10.0" : "3.4.0";
  if (p == bm::hd::kDeviceModelType)
    return "Touch (fake)";
  std::lock_guard<std::mutex> l(F().m);
  PushError(bm::hd::kInvalidEnum, 0);
  return nullptr;
}
void hdEnable(HDenum cap) {
  if (cap == bm::hd::kForceOutput && F().fault.load() == 4)
    std::raise(SIGABRT); // the probe must never enable force output
  std::lock_guard<std::mutex> l(F().m);
  if (cap == bm::hd::kForceOutput)
    F().forceOutput = true;
}
void hdGetDoublev(HDenum p, HDdouble* v) {
  std::lock_guard<std::mutex> l(F().m);
  switch (p) {
  case bm::hd::kCurrentPosition:
    for (int i = 0; i < 3; ++i)
      v[i] = F().position[size_t(i)];
    break;
  case bm::hd::kCurrentTransform:
    for (int i = 0; i < 16; ++i)
      v[i] = (i % 5 == 0) ? 1.0 : 0.0;
    for (int i = 0; i < 3; ++i)
      v[12 + i] = F().position[size_t(i)];
    break;
  case bm::hd::kNominalMaxForce:
    v[0] = F().maxForce;
    break;
  case bm::hd::kNominalMaxStiffness:
    v[0] = F().maxStiffness;
    break;
  case bm::hd::kNominalMaxDamping:
    v[0] = F().maxDamping;
    break;
  default:
    PushError(bm::hd::kInvalidEnum, 0);
  }
}
void hdGetIntegerv(HDenum p, HDint* v) {
  std::lock_guard<std::mutex> l(F().m);
  if (p == bm::hd::kCurrentButtons)
    v[0] = F().buttons;
  else if (p == bm::hd::kUpdateRate)
    v[0] = 1000;
  else
    PushError(bm::hd::kInvalidEnum, 0);
}
void hdSetDoublev(HDenum p, const HDdouble* v) {
  std::lock_guard<std::mutex> l(F().m);
  if (p != bm::hd::kCurrentForce) {
    PushError(bm::hd::kInvalidEnum, 0);
    return;
  }
  if (!F().forceOutput)
    return;
  F().forces.push_back({v[0], v[1], v[2]});
  if (std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) > F().maxForce)
    PushError(bm::hd::kExceededMaxForce, 7);
}
HDErrorInfo hdGetError() {
  std::lock_guard<std::mutex> l(F().m);
  if (F().errors.empty())
    return HDErrorInfo{bm::hd::kSuccess, 0, 1};
  HDErrorInfo e = F().errors.front();
  F().errors.pop_front();
  return e;
}
HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback cb, void* data, HDushort) {
  std::lock_guard<std::mutex> l(F().m);
  F().callbacks.emplace_back(cb, data);
  return HDSchedulerHandle(F().callbacks.size());
}
void hdUnschedule(HDSchedulerHandle h) {
  std::lock_guard<std::mutex> l(F().m);
  if (h >= 1 && h <= F().callbacks.size())
    F().callbacks[h - 1].first = nullptr;
}
void hdStartScheduler() {
  if (F().running.exchange(true))
    return;
  F().scheduler = std::thread([] {
    auto next = std::chrono::steady_clock::now();
    while (F().running.load()) {
      if (!F().stalled.load()) {
        std::vector<std::pair<HDSchedulerCallback, void*>> cbs;
        {
          std::lock_guard<std::mutex> l(F().m);
          cbs = F().callbacks;
        }
        for (auto& [cb, data] : cbs)
          if (cb)
            cb(data);
        F().ticks.fetch_add(1);
      }
      next += std::chrono::milliseconds(1);
      std::this_thread::sleep_until(next);
    }
  });
}
void hdStopScheduler() {
  if (!F().running.exchange(false))
    return;
  if (F().scheduler.joinable())
    F().scheduler.join();
  std::lock_guard<std::mutex> l(F().m);
  F().callbacks.clear();
}

// A process that loads the fake (bmsim in the CLI tests) sets its fault from the environment:
// FAKEHD_FAULT = constructor (SIGSEGV while the library loads), init, hang, old-version, enable,
// servo (the modes of fakeHD_SetFault) or huge-limit (it reports a nominal maximum of 10^6 N).
// Its process writes the largest force it was sent to FAKEHD_FORCE_LOG when the library unloads.
__attribute__((constructor)) static void FakeHDFromEnvironment() {
  const char* f = std::getenv("FAKEHD_FAULT");
  const std::string fault = f ? f : "";
  if (fault == "constructor")
    std::raise(SIGSEGV);
  static const std::pair<const char*, int> modes[] = {
      {"init", 1}, {"hang", 2}, {"old-version", 3}, {"enable", 4}, {"servo", 5}};
  for (const auto& [name, mode] : modes)
    if (fault == name)
      F().fault = mode;
  if (fault == "huge-limit")
    F().maxForce = 1e6;
}
__attribute__((destructor(200))) static void FakeHDLogForces() {
  const char* log = std::getenv("FAKEHD_FORCE_LOG");
  if (!log || !*log)
    return;
  if (FILE* out = std::fopen(log, "w")) {
    double worst = 0;
    for (const auto& v : F().forces)
      worst = std::max(worst, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    std::fprintf(out, "%.9g %zu\n", worst, F().forces.size());
    std::fclose(out);
  }
}
// Last: the state goes with the library (LeakSanitizer counts what an unloaded library still
// held), unless a scheduler thread still runs on it.
__attribute__((destructor(101))) static void FakeHDFreeState() {
  Fake* f = FakeState();
  if (f->scheduler.joinable())
    return;
  delete f;
  FakeState() = nullptr;
}

// Test controls.
void fakeHD_Reset() {
  std::lock_guard<std::mutex> l(F().m);
  F().position = {0, 0, 0};
  F().buttons = 0;
  F().forces.clear();
  F().errors.clear();
  F().stalled = false;
  F().initError = 0;
  F().fault = 0;
  F().maxForce = 3.3;
}
// 0: none; 1: hdInitDevice raises SIGSEGV; 2: hdInitDevice blocks until the mode changes;
// 3: hdGetString(HD_VERSION) says "2.10.0"; 4: hdEnable(HD_FORCE_OUTPUT) raises SIGABRT;
// 5: hdBeginFrame (in the servo callback) raises SIGSEGV.
void fakeHD_SetFault(int mode) {
  F().fault = mode;
}
// The nominal maximum force the fake reports (N); a faulty driver may claim anything.
void fakeHD_SetMaxForce(double n) {
  std::lock_guard<std::mutex> l(F().m);
  F().maxForce = n;
}
// The largest force magnitude written with hdSetDoublev(HD_CURRENT_FORCE) so far (N).
double fakeHD_MaxForceSent() {
  std::lock_guard<std::mutex> l(F().m);
  double worst = 0;
  for (const auto& f : F().forces)
    worst = std::max(worst, std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
  return worst;
}
void fakeHD_SetPosition(double x, double y, double z) {
  std::lock_guard<std::mutex> l(F().m);
  F().position = {x, y, z};
}
void fakeHD_InjectError(unsigned code, int internal) {
  std::lock_guard<std::mutex> l(F().m);
  PushError(code, internal);
}
void fakeHD_FailInit(unsigned code) {
  std::lock_guard<std::mutex> l(F().m);
  F().initError = int(code);
}
void fakeHD_SetStalled(int s) {
  F().stalled = s != 0;
}
long fakeHD_ForceCount() {
  std::lock_guard<std::mutex> l(F().m);
  return long(F().forces.size());
}
int fakeHD_GetForce(long i, double* out) {
  std::lock_guard<std::mutex> l(F().m);
  if (i < 0 || size_t(i) >= F().forces.size())
    return 0;
  for (int a = 0; a < 3; ++a)
    out[a] = F().forces[size_t(i)][size_t(a)];
  return 1;
}
int fakeHD_ForceOutputEnabled() {
  std::lock_guard<std::mutex> l(F().m);
  return F().forceOutput ? 1 : 0;
}
int fakeHD_SchedulerRunning() {
  return F().running.load() ? 1 : 0;
}
long fakeHD_Ticks() {
  return F().ticks.load();
}
}
