// The Touch device through the fake libHD.so (Testing/Logic/Session/FakeHD): the dlopen path,
// init, force output, servo callback, limits query, error codes, a stalled servo loop, and a
// session that pauses with zero force when the device reports an error; the library checks and
// the probe (bmTouchProbe.h) against libraries that crash, hang, lack a symbol, are cut short or
// too old.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "bmHapticSession.h"
#include "bmSessionTestUtil.h"
#include "bmTouchDevice.h"
#include "bmHapticDeviceModel.h"
#include "bmTouchProbe.h"

namespace {

struct FakeHD {
  void* lib = nullptr;
  void (*reset)() = nullptr;
  void (*setPosition)(double, double, double) = nullptr;
  void (*injectError)(unsigned, int) = nullptr;
  void (*failInit)(unsigned) = nullptr;
  void (*setStalled)(int) = nullptr;
  long (*forceCount)() = nullptr;
  int (*getForce)(long, double*) = nullptr;
  int (*forceOutput)() = nullptr;
  int (*schedulerRunning)() = nullptr;
  void (*setFault)(int) = nullptr;
  FakeHD() {
    lib = dlopen(BM_FAKE_HD_PATH, RTLD_NOW | RTLD_LOCAL);
    if (!lib)
      return;
    reset = reinterpret_cast<void (*)()>(dlsym(lib, "fakeHD_Reset"));
    setPosition =
        reinterpret_cast<void (*)(double, double, double)>(dlsym(lib, "fakeHD_SetPosition"));
    injectError = reinterpret_cast<void (*)(unsigned, int)>(dlsym(lib, "fakeHD_InjectError"));
    failInit = reinterpret_cast<void (*)(unsigned)>(dlsym(lib, "fakeHD_FailInit"));
    setStalled = reinterpret_cast<void (*)(int)>(dlsym(lib, "fakeHD_SetStalled"));
    forceCount = reinterpret_cast<long (*)()>(dlsym(lib, "fakeHD_ForceCount"));
    getForce = reinterpret_cast<int (*)(long, double*)>(dlsym(lib, "fakeHD_GetForce"));
    forceOutput = reinterpret_cast<int (*)()>(dlsym(lib, "fakeHD_ForceOutputEnabled"));
    schedulerRunning = reinterpret_cast<int (*)()>(dlsym(lib, "fakeHD_SchedulerRunning"));
    setFault = reinterpret_cast<void (*)(int)>(dlsym(lib, "fakeHD_SetFault"));
    reset();
  }
  ~FakeHD() {
    if (lib)
      dlclose(lib);
  }
  Eigen::Vector3d Force(long i) const {
    double f[3] = {0, 0, 0};
    getForce(i, f);
    return {f[0], f[1], f[2]};
  }
};

void WaitMs(int ms) {
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

// Start()'s error message, or "not reported" when it did not throw.
std::string StartError(bm::TouchDevice& touch) {
  try {
    touch.Start();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "not reported";
}

// Waits until the servo loop has run n more callbacks (at most timeoutS): a fixed sleep is not
// enough on a loaded CI machine, where the servo thread may not be scheduled for tens of ms.
bool WaitForTicks(const bm::TouchDevice& touch, uint64_t n, double timeoutS = 5.0) {
  const uint64_t t0 = touch.ServoTicks();
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  while (touch.ServoTicks() < t0 + n) {
    if (std::chrono::steady_clock::now() > until)
      return false;
    WaitMs(1);
  }
  return true;
}

// Reads the pose once the servo loop has run again, retrying (at most 100 times) while the read
// says NoResponse: a test thread descheduled for longer than the stall timeout reads a stale
// sample, which is the device's job to report, not a fault of the device under test.
bm::DeviceStatus ReadFresh(bm::TouchDevice& touch, bm::DevicePose& p) {
  bm::DeviceStatus s = bm::DeviceStatus::NoResponse;
  for (int i = 0; i < 100 && s == bm::DeviceStatus::NoResponse; ++i)
    if (WaitForTicks(touch, 1))
      s = touch.Read(p);
  return s;
}

TEST(TouchDevice, LoadsTheLibraryInitialisesAndRunsTheServoLoop) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr) << dlerror();
  fake.setPosition(1.5, -2.0, 30.0);
  bm::TouchDevice touch(BM_FAKE_HD_PATH);
  touch.Start();
  EXPECT_EQ(fake.forceOutput(), 1);
  EXPECT_EQ(fake.schedulerRunning(), 1);
  // Limits come from the driver (the fake reports 0.35 N/mm, unlike the published 0.4).
  EXPECT_DOUBLE_EQ(touch.Limits().maxStiffnessNPerMm, 0.35);
  EXPECT_DOUBLE_EQ(touch.Limits().maxForceN, 3.3);
  EXPECT_DOUBLE_EQ(touch.Limits().maxDampingNsPerMm, 0.003);
  // Start() returns with the servo loop's first sample in hand: the very first Read() is the
  // stylus's measured pose, never the default origin (CI once caught a zero pose here).
  // (A machine that starves both threads past the stall timeout makes it NoResponse instead.)
  EXPECT_GE(touch.ServoTicks(), 1u);
  bm::DevicePose p;
  const bm::DeviceStatus first = touch.Read(p);
  if (first != bm::DeviceStatus::NoResponse) {
    ASSERT_EQ(first, bm::DeviceStatus::Ok);
    EXPECT_DOUBLE_EQ(p.positionMm(0), 1.5);
    EXPECT_DOUBLE_EQ(p.positionMm(1), -2.0);
    EXPECT_DOUBLE_EQ(p.positionMm(2), 30.0);
  }
  // A write may find the servo copying the force out and land next frame, as in the session,
  // which writes every frame: write until the device has output it.
  const Eigen::Vector3d f(0.1, 0.2, 0.3);
  bool sent = false;
  for (int i = 0; i < 100 && !sent; ++i) {
    ASSERT_EQ(touch.Write(f), bm::DeviceStatus::Ok);
    ASSERT_TRUE(WaitForTicks(touch, 2)) << "servo loop stopped";
    const long n = fake.forceCount();
    sent = n > 0 && fake.Force(n - 1).isApprox(f);
  }
  EXPECT_TRUE(sent);
  ASSERT_EQ(ReadFresh(touch, p), bm::DeviceStatus::Ok);
  EXPECT_DOUBLE_EQ(p.positionMm(0), 1.5);
  EXPECT_DOUBLE_EQ(p.positionMm(2), 30.0);
  touch.Stop();
  EXPECT_EQ(fake.schedulerRunning(), 0);
  // The last force the device got is zero.
  EXPECT_EQ(fake.Force(fake.forceCount() - 1), Eigen::Vector3d::Zero());
}

TEST(TouchDevice, ReportsErrorCodesAndAStalledServoLoop) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr);
  {
    bm::TouchDevice touch(BM_FAKE_HD_PATH);
    touch.Start();
    fake.injectError(bm::hd::kCommError, 17);
    ASSERT_TRUE(WaitForTicks(touch, 2));
    bm::DevicePose p;
    EXPECT_EQ(touch.Read(p), bm::DeviceStatus::Error);
    EXPECT_NE(touch.LastError().find("HD_COMM_ERROR"), std::string::npos) << touch.LastError();
    touch.Stop();
  }
  fake.reset();
  {
    bm::TouchDevice touch(BM_FAKE_HD_PATH, 0.02);
    touch.Start();
    bm::DevicePose p;
    EXPECT_EQ(ReadFresh(touch, p), bm::DeviceStatus::Ok);
    fake.setStalled(1);
    WaitMs(60);
    EXPECT_EQ(touch.Read(p), bm::DeviceStatus::NoResponse);
    fake.setStalled(0);
    touch.Stop();
  }
  fake.reset();
  {
    // A servo loop that never runs: Start() gives up after its timeout, names the cause, and
    // leaves the device closed (force output off, scheduler stopped).
    fake.setStalled(1);
    bm::TouchDevice silent(BM_FAKE_HD_PATH);
    const std::string error = StartError(silent);
    EXPECT_NE(error.find("no sample"), std::string::npos) << error;
    EXPECT_EQ(fake.schedulerRunning(), 0);
    bm::DevicePose p;
    EXPECT_EQ(silent.Read(p), bm::DeviceStatus::NoResponse);
    fake.setStalled(0);
  }
  fake.reset();
  fake.failInit(bm::hd::kDeviceFault);
  bm::TouchDevice broken(BM_FAKE_HD_PATH);
  const std::string error = StartError(broken);
  EXPECT_NE(error.find("HD_DEVICE_FAULT"), std::string::npos) << error;
  fake.reset();
  bm::TouchDevice missing("/nonexistent/libHD.so");
  EXPECT_THROW(missing.Start(), std::runtime_error);
}

TEST(TouchDevice, ANonFinitePoseOrAnErrorZeroesTheForceInTheServoLoopItself) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr);
  // Whatever the session wrote last, a servo tick that reads a non-finite pose sends zero, and
  // so does every tick after it (the error is latched): the force does not wait for the session.
  for (bool nanPose : {true, false}) {
    fake.reset();
    bm::TouchDevice touch(BM_FAKE_HD_PATH);
    touch.Start();
    touch.Write({0, 0, 1.0});
    ASSERT_TRUE(WaitForTicks(touch, 3));
    const long n0 = fake.forceCount();
    ASSERT_GT(n0, 0);
    EXPECT_EQ(fake.Force(n0 - 1), Eigen::Vector3d(0, 0, 1.0));
    if (nanPose)
      fake.setPosition(std::nan(""), 0, 0);
    else
      fake.injectError(bm::hd::kCommError, 5);
    ASSERT_TRUE(WaitForTicks(touch, 3));
    touch.Write({0, 0, 1.0}); // a session that had not noticed yet
    ASSERT_TRUE(WaitForTicks(touch, 5));
    bm::DevicePose p;
    EXPECT_EQ(touch.Read(p), bm::DeviceStatus::Error);
    if (nanPose) {
      EXPECT_NE(touch.LastError().find("non-finite pose"), std::string::npos) << touch.LastError();
    }
    const long n1 = fake.forceCount();
    long firstZero = -1;
    for (long i = n0; i < n1; ++i)
      if (fake.Force(i).isZero(0.0) && firstZero < 0)
        firstZero = i;
    ASSERT_GE(firstZero, 0) << (nanPose ? "NaN pose" : "error") << ": the force never went to zero";
    // Zero from the tick that saw the NaN (it is read before the force is sent), or from the
    // tick after the error was reported, and never anything else again, even though the last
    // write asked for 1 N.
    for (long i = firstZero; i < n1; ++i)
      ASSERT_TRUE(fake.Force(i).isZero(0.0)) << "tick " << i << " after the fault sent force";
    touch.Stop();
  }
}

TEST(TouchDevice, SessionSendsOnlyLimitedForcesAndPausesWithZeroForceOnADeviceError) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr);
  // Burr resting 0.3 mm inside a block (spindle stopped): the coupling pulls the stylus out.
  bm::MachiningSetup setup(bm::test::BurrScene(0.5, {3, 3, 1.5}, 48, 64),
                           bm::MakeSceneBlock(bm::test::BurrScene(0.5, {3, 3, 1.5}, 48, 64)));
  fake.setPosition(0, 0, 0.1);
  auto touch = std::make_shared<bm::TouchDevice>(BM_FAKE_HD_PATH);
  bm::SessionOptions o;
  o.speedRpm = 0;
  o.overrunLimit = -1; // sanitizer builds run slowly: only the device fault is under test here
  bm::HapticSession session(setup, touch, o);
  session.Start();
  WaitMs(30);
  fake.setPosition(0, 0, -20.0); // plunge 20 mm: the coupling wants 8 N, the device may take 3.3 N
  // The coupling reaches the device's limit within tens of frames; a loaded machine may take
  // longer to schedule them, so poll (at most 5 s) instead of sleeping a fixed time.
  bm::SessionSnapshot s = session.Snapshot();
  for (int i = 0; i < 500 && !(s.deviceForceN(2) > 3.0); ++i) {
    WaitMs(10);
    s = session.Snapshot();
  }
  EXPECT_EQ(s.state, bm::SessionState::Running);
  EXPECT_GT(s.deviceForceN(2), 3.0);
  const long before = fake.forceCount();
  ASSERT_GT(before, 0);
  double maxF = 0;
  for (long i = 0; i < before; ++i)
    maxF = std::max(maxF, fake.Force(i).norm());
  EXPECT_LE(maxF, touch->Limits().maxForceN);
  fake.injectError(bm::hd::kExceededMaxVelocity, 3);
  ASSERT_TRUE(session.WaitUntilPaused(2.0));
  WaitMs(20);
  s = session.Snapshot();
  EXPECT_EQ(s.state, bm::SessionState::Paused);
  EXPECT_EQ(s.pauseReason, bm::PauseReason::DeviceError);
  EXPECT_EQ(fake.Force(fake.forceCount() - 1), Eigen::Vector3d::Zero());
  session.Stop();
  std::cout << "[touch] " << before << " servo forces before the fault, max |F| " << maxF
            << " N (limit " << touch->Limits().maxForceN << " N)\n";
}

// A scratch folder for library files made by the tests, removed at the end.
struct ScratchDir {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("bm_touch_probe_" + std::to_string(::getpid()));
  ScratchDir() { std::filesystem::create_directories(path); }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string Write(const std::string& name, const std::string& bytes) const {
    const auto file = path / name;
    std::ofstream(file, std::ios::binary) << bytes;
    return file.string();
  }
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(TouchProbe, OpensTheDeviceRunsItsServoLoopAtZeroForceAndReportsItsVersionAndLimits) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr) << dlerror();
  const bm::TouchProbeResult r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  EXPECT_TRUE(r.ready) << r.message;
  EXPECT_EQ(r.message, "");
  EXPECT_EQ(r.library, BM_FAKE_HD_PATH);
  EXPECT_EQ(r.version, "3.4.0");
  EXPECT_EQ(r.model, "Touch (fake)");
  EXPECT_DOUBLE_EQ(r.limits.maxStiffnessNPerMm, 0.35); // the driver's, not the published 0.4
  EXPECT_DOUBLE_EQ(r.limits.maxDampingNsPerMm, 0.003);
  EXPECT_DOUBLE_EQ(r.limits.rateHz, 1000);
  // The caller's own copy of the library was never touched.
  EXPECT_EQ(fake.forceOutput(), 0);
  EXPECT_EQ(fake.schedulerRunning(), 0);
  EXPECT_THROW(bm::ProbeTouch(0.0, BM_FAKE_HD_PATH), std::invalid_argument);
  EXPECT_THROW(bm::ProbeTouch(std::nan(""), BM_FAKE_HD_PATH), std::invalid_argument);
}

TEST(TouchProbe, ALibraryThatCrashesOrHangsEndsOnlyTheProbeAndIsNamed) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr);
  fake.setFault(1); // SIGSEGV inside hdInitDevice
  bm::TouchProbeResult r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  EXPECT_FALSE(r.ready);
  EXPECT_TRUE(Has(r.message, "crashed during hdInitDevice")) << r.message;
  EXPECT_TRUE(Has(r.message, "SIGSEGV")) << r.message;
  fake.setFault(2); // hdInitDevice never returns
  const auto t0 = std::chrono::steady_clock::now();
  r = bm::ProbeTouch(0.5, BM_FAKE_HD_PATH);
  const double waitedS =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  fake.setFault(0);
  EXPECT_FALSE(r.ready);
  EXPECT_TRUE(Has(r.message, "did not answer within 0.5 s (hung during hdInitDevice)"))
      << r.message;
  EXPECT_LT(waitedS, 5.0); // the timeout and the reaping, not the hang
  fake.setFault(3);
  r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  fake.setFault(0);
  EXPECT_FALSE(r.ready);
  EXPECT_TRUE(Has(r.message, "HD API version 2.10.0, older than 3")) << r.message;
  fake.failInit(bm::hd::kDeviceFault);
  r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  fake.reset();
  EXPECT_TRUE(Has(r.message, "hdInitDevice failed: HD_DEVICE_FAULT")) << r.message;
  // Faults where a session goes next: enabling force output, the servo callback.
  fake.setFault(4); // SIGABRT in hdEnable(HD_FORCE_OUTPUT)
  r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  EXPECT_FALSE(r.ready);
  EXPECT_TRUE(Has(r.message, "crashed during hdEnable(HD_FORCE_OUTPUT)")) << r.message;
  EXPECT_TRUE(Has(r.message, "SIGABRT")) << r.message;
  fake.setFault(5); // SIGSEGV in hdBeginFrame, inside the servo callback
  r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  fake.setFault(0);
  EXPECT_FALSE(r.ready);
  EXPECT_TRUE(Has(r.message, "crashed during the servo callback")) << r.message;
  EXPECT_TRUE(Has(r.message, "SIGSEGV")) << r.message;
}

TEST(TouchDevice, ForceIsCappedAtTheModelsOwnLimitWhateverTheDriverClaims) {
  EXPECT_DOUBLE_EQ(bm::PublishedMaxForceN("Touch"), 3.3);
  EXPECT_DOUBLE_EQ(bm::PublishedMaxForceN("PHANTOM Omni"), 3.3);
  EXPECT_DOUBLE_EQ(bm::PublishedMaxForceN("Touch X"), 7.9);
  EXPECT_DOUBLE_EQ(bm::PublishedMaxForceN("PHANTOM Premium 1.5 High Force"), 37.5);
  EXPECT_DOUBLE_EQ(bm::PublishedMaxForceN("something else"), 3.3);
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr);
  auto setMaxForce = reinterpret_cast<void (*)(double)>(dlsym(fake.lib, "fakeHD_SetMaxForce"));
  auto maxSent = reinterpret_cast<double (*)()>(dlsym(fake.lib, "fakeHD_MaxForceSent"));
  ASSERT_TRUE(setMaxForce && maxSent);
  setMaxForce(1e6); // a driver claiming a million newtons
  const bm::TouchProbeResult r = bm::ProbeTouch(10.0, BM_FAKE_HD_PATH);
  ASSERT_TRUE(r.ready) << r.message;
  EXPECT_DOUBLE_EQ(r.limits.maxForceN, 3.3);
  {
    bm::TouchDevice touch(BM_FAKE_HD_PATH);
    touch.Start();
    EXPECT_DOUBLE_EQ(touch.Limits().maxForceN, 3.3);
    // Whatever is written, the motors get at most the model's limit.
    touch.Write(Eigen::Vector3d(50000, 0, 0));
    ASSERT_TRUE(WaitForTicks(touch, 5));
    touch.Stop();
  }
  EXPECT_GT(maxSent(), 3.0);
  EXPECT_LE(maxSent(), 3.3);
  setMaxForce(3.3);
}

TEST(TouchProbe, RefusesMissingSymbolsAndDamagedFilesBeforeCallingThem) {
  ScratchDir dir;
  const std::string good = ReadFile(BM_FAKE_HD_PATH);
  ASSERT_GT(good.size(), 8192u);
  struct Case {
    std::string path, expected;
  };
  const std::vector<Case> cases = {
      {BM_FAKE_HD_NO_END_FRAME_PATH, "has no symbol hdEndFrame"},
      {dir.Write("libHD-cut.so", good.substr(0, 4096)),
       "is not a usable shared library: truncated"},
      {dir.Write("libHD-header.so", good.substr(0, 40)),
       "truncated: too short for an ELF header (40 bytes)"},
      {dir.Write("libHD-text.so", "#!/bin/sh\necho not a library\n"), "not an ELF file"},
      {dir.path.string(), "not a regular file"},
      {"/nonexistent/libHD.so", "cannot be read"},
  };
  for (const Case& c : cases) {
    const bm::TouchProbeResult r = bm::ProbeTouch(10.0, c.path);
    EXPECT_FALSE(r.ready) << c.path;
    EXPECT_TRUE(Has(r.message, c.expected)) << c.path << ": " << r.message;
    EXPECT_TRUE(Has(r.message, c.path)) << r.message;
    // The device itself runs the same checks in-process before calling anything (dlopen of the
    // cut library would fault with SIGBUS).
    bm::TouchDevice touch(c.path);
    const std::string error = StartError(touch);
    EXPECT_TRUE(Has(error, c.expected)) << c.path << ": " << error;
  }
}

TEST(TouchDevice, StartGivesUpOnAnHdInitDeviceThatNeverReturns) {
  FakeHD fake;
  ASSERT_NE(fake.lib, nullptr);
  EXPECT_THROW(bm::TouchDevice(BM_FAKE_HD_PATH, 0.05, 0.0), std::invalid_argument);
  EXPECT_THROW(bm::TouchDevice(BM_FAKE_HD_PATH, -1.0), std::invalid_argument);
  fake.setFault(2);
  {
    bm::TouchDevice touch(BM_FAKE_HD_PATH, 0.05, 0.3);
    const auto t0 = std::chrono::steady_clock::now();
    const std::string error = StartError(touch);
    const double waitedS =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(Has(error, "hdInitDevice did not return within 0.3 s")) << error;
    EXPECT_LT(waitedS, 5.0);
    EXPECT_EQ(fake.forceOutput(), 0);
    bm::DevicePose p;
    EXPECT_EQ(touch.Read(p), bm::DeviceStatus::NoResponse);
  }
  fake.setFault(0); // the abandoned call returns; the device opens normally after it
  WaitMs(50);
  fake.reset();
  bm::TouchDevice touch(BM_FAKE_HD_PATH);
  touch.Start();
  EXPECT_EQ(fake.forceOutput(), 1);
  touch.Stop();
}

} // namespace
