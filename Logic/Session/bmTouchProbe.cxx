#include "bmTouchProbe.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "bmHDApi.h"
#include "bmHapticDeviceModel.h"
#include "bmSharedLibraryCheck.h"

namespace bm {

namespace {

/// Servo callbacks the probe waits for (about 50 ms at the Touch's 1 kHz).
constexpr int kProbeServoTicks = 50;

// One line of at most 300 printable characters (a library's strings go into the protocol).
std::string OneLine(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 300))
    out += (c >= 32 && c < 127) ? c : ' ';
  return out;
}

void Emit(int fd, const std::string& line) {
  const std::string text = OneLine(line) + "\n";
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      _exit(3); // the parent is gone
    done += size_t(n);
  }
}

// The probe's servo callback (in the child): what the session's does, at zero force.
struct ProbeServo {
  void (*beginFrame)(HHD) = nullptr;
  void (*endFrame)(HHD) = nullptr;
  void (*getDoublev)(HDenum, HDdouble*) = nullptr;
  void (*setDoublev)(HDenum, const HDdouble*) = nullptr;
  HHD device = hd::kInvalidHandle;
  std::atomic<int> ticks{0};
};
ProbeServo g_servo;

HDCallbackCode ProbeServoTick(void*) {
  g_servo.beginFrame(g_servo.device);
  HDdouble pos[3] = {0, 0, 0}, m[16] = {};
  g_servo.getDoublev(hd::kCurrentPosition, pos);
  g_servo.getDoublev(hd::kCurrentTransform, m);
  const HDdouble zero[3] = {0, 0, 0};
  g_servo.setDoublev(hd::kCurrentForce, zero);
  g_servo.endFrame(g_servo.device);
  g_servo.ticks.fetch_add(1);
  return hd::kCallbackContinue;
}

// The child: every step announced before it is taken, the answer last. Never returns.
[[noreturn]] void ProbeChild(int fd, const std::string& name) {
  for (int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGTERM})
    signal(sig, SIG_DFL); // a crash is the parent's answer, not a handler's report
  signal(SIGPIPE, SIG_IGN);
  const auto fail = [&](const std::string& message) {
    Emit(fd, "error touch: " + message);
    _exit(0);
  };
  try {
    Emit(fd, "step checking the library file");
    const std::string file = FindSharedLibrary(name);
    if (!file.empty()) {
      Emit(fd, "library " + file);
      CheckSharedLibraryFile(file);
    }
    Emit(fd, "step dlopen");
    void* lib = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      const char* why = dlerror();
      fail("cannot load '" + name + "': " + (why ? why : "unknown error"));
    }
    Emit(fd, "step checking the library's symbols");
    for (const char* symbol : hd::kRequiredSymbols)
      BindLibraryFunction(lib, symbol, name);
    auto init = reinterpret_cast<HHD (*)(HDstring)>(BindLibraryFunction(lib, "hdInitDevice", name));
    auto disable =
        reinterpret_cast<void (*)(HHD)>(BindLibraryFunction(lib, "hdDisableDevice", name));
    auto makeCurrent =
        reinterpret_cast<void (*)(HHD)>(BindLibraryFunction(lib, "hdMakeCurrentDevice", name));
    auto getError =
        reinterpret_cast<HDErrorInfo (*)()>(BindLibraryFunction(lib, "hdGetError", name));
    auto getDoublev = reinterpret_cast<void (*)(HDenum, HDdouble*)>(
        BindLibraryFunction(lib, "hdGetDoublev", name));
    auto getIntegerv =
        reinterpret_cast<void (*)(HDenum, HDint*)>(BindLibraryFunction(lib, "hdGetIntegerv", name));
    HDstring (*getString)(HDenum) = nullptr;
    if (dlsym(lib, hd::kVersionSymbol))
      getString = reinterpret_cast<HDstring (*)(HDenum)>(
          BindLibraryFunction(lib, hd::kVersionSymbol, name));
    const auto check = [&](const std::string& step) {
      const HDErrorInfo e = getError();
      if (e.errorCode != hd::kSuccess)
        fail(step + " failed: " + hd::ErrorName(e.errorCode) + " (device code " +
             std::to_string(e.internalErrorCode) + ")");
    };
    auto enable = reinterpret_cast<void (*)(HDenum)>(BindLibraryFunction(lib, "hdEnable", name));
    auto schedule = reinterpret_cast<HDSchedulerHandle (*)(HDSchedulerCallback, void*, HDushort)>(
        BindLibraryFunction(lib, "hdScheduleAsynchronous", name));
    auto unschedule = reinterpret_cast<void (*)(HDSchedulerHandle)>(
        BindLibraryFunction(lib, "hdUnschedule", name));
    auto startScheduler =
        reinterpret_cast<void (*)()>(BindLibraryFunction(lib, "hdStartScheduler", name));
    auto stopScheduler =
        reinterpret_cast<void (*)()>(BindLibraryFunction(lib, "hdStopScheduler", name));
    g_servo.beginFrame =
        reinterpret_cast<void (*)(HHD)>(BindLibraryFunction(lib, "hdBeginFrame", name));
    g_servo.endFrame =
        reinterpret_cast<void (*)(HHD)>(BindLibraryFunction(lib, "hdEndFrame", name));
    g_servo.getDoublev = getDoublev;
    g_servo.setDoublev = reinterpret_cast<void (*)(HDenum, const HDdouble*)>(
        BindLibraryFunction(lib, "hdSetDoublev", name));
    Emit(fd, "step hdInitDevice");
    const HHD device = init(nullptr); // HD_DEFAULT_DEVICE; force output stays off
    check("hdInitDevice");
    if (device == hd::kInvalidHandle)
      fail("hdInitDevice returned no device");
    makeCurrent(device);
    if (getString) {
      Emit(fd, "step hdGetString(HD_VERSION)");
      const char* version = getString(hd::kVersion);
      const std::string v = version ? OneLine(version) : "";
      Emit(fd, "version " + v);
      if (!v.empty() && v[0] >= '0' && v[0] <= '9' &&
          std::atoi(v.c_str()) < hd::kMinimumMajorVersion)
        fail("'" + name + "' is HD API version " + v + ", older than " +
             std::to_string(hd::kMinimumMajorVersion) + " (OpenHaptics 3 drives the Touch)");
      Emit(fd, "step hdGetString(HD_DEVICE_MODEL_TYPE)");
      const char* model = getString(hd::kDeviceModelType);
      Emit(fd, std::string("model ") + (model ? model : ""));
      check("hdGetString");
    }
    Emit(fd, "step querying the nominal limits");
    HDdouble force = 0, stiffness = 0, damping = 0;
    HDint rate = 0;
    getDoublev(hd::kNominalMaxForce, &force);
    getDoublev(hd::kNominalMaxStiffness, &stiffness);
    getDoublev(hd::kNominalMaxDamping, &damping);
    getIntegerv(hd::kUpdateRate, &rate);
    check("querying the nominal limits");
    std::ostringstream limits;
    limits.precision(17);
    limits << "limits " << force << " " << stiffness << " " << damping << " " << rate;
    Emit(fd, limits.str());
    // What a session does next, at zero force: a driver that faults there ends only this child.
    Emit(fd, "step hdEnable(HD_FORCE_OUTPUT)");
    enable(hd::kForceOutput);
    check("hdEnable(HD_FORCE_OUTPUT)");
    Emit(fd, "step the servo callback (zero force)");
    g_servo.device = device;
    const HDSchedulerHandle callback =
        schedule(&ProbeServoTick, nullptr, hd::kMaxSchedulerPriority);
    check("hdScheduleAsynchronous");
    startScheduler();
    check("hdStartScheduler");
    const auto started = std::chrono::steady_clock::now();
    while (g_servo.ticks.load() < kProbeServoTicks) {
      if (std::chrono::steady_clock::now() - started > std::chrono::seconds(2))
        fail("the servo loop ran " + std::to_string(g_servo.ticks.load()) +
             " callbacks in 2 s of hdStartScheduler");
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    check("the servo callback");
    Emit(fd, "step hdStopScheduler");
    stopScheduler();
    unschedule(callback);
    Emit(fd, "step hdDisableDevice");
    disable(device);
    Emit(fd, "ok");
  } catch (const std::exception& e) {
    fail(e.what());
  }
  _exit(0);
}

std::string Seconds(double s) {
  std::ostringstream out;
  out << s;
  return out.str();
}

std::string SignalName(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  const char* description = sigdescr_np(sig);
  return "signal " + std::to_string(sig) + (abbrev ? std::string(", SIG") + abbrev : "") +
         (description ? std::string(", ") + description : "");
}

} // namespace

TouchProbeResult ProbeTouch(double timeoutS, std::string libraryPath) {
  if (!std::isfinite(timeoutS) || timeoutS <= 0 || timeoutS > 600)
    throw std::invalid_argument("ProbeTouch: timeout " + std::to_string(timeoutS) +
                                " s is outside (0, 600] s");
  if (libraryPath.empty()) {
    const char* env = std::getenv("BM_LIBHD");
    libraryPath = env && *env ? env : "libHD.so";
  }
  TouchProbeResult result;
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    result.message =
        std::string("touch: cannot open a pipe for the probe: ") + std::strerror(errno);
    return result;
  }
  const pid_t pid = fork();
  if (pid < 0) {
    result.message = std::string("touch: cannot start the probe process: ") + std::strerror(errno);
    close(fds[0]);
    close(fds[1]);
    return result;
  }
  if (pid == 0) {
    close(fds[0]);
    setpgid(0, 0); // its own group: a hung library's helpers are killed with it
    ProbeChild(fds[1], libraryPath);
  }
  setpgid(pid, pid); // also from here, whichever runs first
  close(fds[1]);
  std::string answer;
  bool timedOut = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  for (;;) {
    const double left =
        std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      timedOut = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, int(std::ceil(left * 1000)));
    if (ready < 0 && errno == EINTR)
      continue;
    if (ready <= 0)
      continue; // the deadline is checked above
    char buffer[4096];
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      break; // EOF: the child has finished or died
    if (answer.size() < 65536)
      answer.append(buffer, size_t(n));
  }
  close(fds[0]);
  if (timedOut) {
    kill(-pid, SIGKILL);
    kill(pid, SIGKILL);
  }
  int status = 0;
  bool reaped = false;
  for (;;) {
    const pid_t r = waitpid(pid, &status, 0);
    if (r < 0 && errno == EINTR)
      continue;
    reaped = r == pid;
    break;
  }
  // Parse the child's lines.
  std::string step = "starting", error;
  bool ok = false;
  std::istringstream lines(answer);
  for (std::string line; std::getline(lines, line);) {
    const size_t space = line.find(' ');
    const std::string key = line.substr(0, space);
    const std::string value = space == std::string::npos ? "" : line.substr(space + 1);
    if (key == "step")
      step = value;
    else if (key == "library")
      result.library = value;
    else if (key == "version")
      result.version = value;
    else if (key == "model")
      result.model = value;
    else if (key == "error")
      error = value;
    else if (key == "ok")
      ok = true;
    else if (key == "limits") {
      std::istringstream in(value);
      double force = 0, stiffness = 0, damping = 0, rate = 0;
      in >> force >> stiffness >> damping >> rate;
      if (std::isfinite(force) && force > 0)
        result.limits.maxForceN = force;
      if (std::isfinite(stiffness) && stiffness > 0)
        result.limits.maxStiffnessNPerMm = stiffness;
      if (std::isfinite(damping) && damping > 0)
        result.limits.maxDampingNsPerMm = damping;
      if (std::isfinite(rate) && rate > 0)
        result.limits.rateHz = rate;
    }
  }
  result.limits = CapToModel(result.limits, result.model); // the model's own peak force at most
  const std::string lib = "'" + libraryPath + "'";
  if (timedOut) {
    result.message = "touch: " + lib + " did not answer within " + Seconds(timeoutS) +
                     " s (hung during " + step + "); the probe was killed";
  } else if (!error.empty()) {
    result.message = error;
  } else if (reaped && WIFSIGNALED(status)) {
    result.message =
        "touch: " + lib + " crashed during " + step + " (" + SignalName(WTERMSIG(status)) + ")";
  } else if (ok && (!reaped || (WIFEXITED(status) && WEXITSTATUS(status) == 0))) {
    // (not reaped: a caller that ignores SIGCHLD has the child reaped by the kernel)
    result.ready = true;
  } else {
    result.message =
        "touch: " + lib + " ended the probe during " + step +
        (reaped && WIFEXITED(status) ? " (exit status " + std::to_string(WEXITSTATUS(status)) + ")"
                                     : std::string(" (no answer)"));
  }
  if (!result.ready)
    result.limits = DeviceLimits{};
  return result;
}

} // namespace bm
