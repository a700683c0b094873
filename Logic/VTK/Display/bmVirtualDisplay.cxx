#include "bmVirtualDisplay.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <poll.h>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace bm {

std::unique_ptr<VirtualDisplay> VirtualDisplay::Start(double timeoutS) {
  const char* d = std::getenv("DISPLAY");
  if (d && *d)
    return nullptr;
  int fds[2];  // Xvfb writes its display number here
  int life[2]; // the keeper reads end-of-file here once this process has ended
  if (::pipe(fds) != 0)
    throw std::runtime_error(std::string("cannot start Xvfb: pipe: ") + std::strerror(errno));
  if (::pipe2(life, O_CLOEXEC) != 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string("cannot start Xvfb: pipe: ") + std::strerror(errno));
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (int f : {fds[0], fds[1], life[0], life[1]})
      ::close(f);
    throw std::runtime_error(std::string("cannot start Xvfb: fork: ") + std::strerror(errno));
  }
  if (pid == 0) {
    // The keeper: starts Xvfb, then waits until this process ends, however it ends (SIGKILL
    // included: the kernel closes the write end of `life`), and stops Xvfb. Only
    // async-signal-safe calls here: the process may have other threads.
    ::close(fds[0]);
    ::close(life[1]);
    const pid_t xvfb = ::fork();
    if (xvfb == 0) {
      ::close(life[0]);
      ::prctl(PR_SET_PDEATHSIG, SIGKILL); // the keeper killed: Xvfb goes with it
      const std::string fd = std::to_string(fds[1]);
      // Keep Xvfb's chatter off the terminal.
      if (int null = ::open("/dev/null", O_WRONLY); null >= 0) {
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
      }
      ::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24",
               "-nolisten", "tcp", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    char c = 0;
    while (::read(life[0], &c, 1) < 0 && errno == EINTR) {
    }
    int status = 0;
    if (xvfb > 0) {
      ::kill(xvfb, SIGTERM);
      ::waitpid(xvfb, &status, 0);
    }
    ::_exit(WIFEXITED(status) ? WEXITSTATUS(status) : 0);
  }
  ::close(fds[1]);
  ::close(life[0]);
  std::string number;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
      break;
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, int(left.count())) <= 0)
      break;
    char c = 0;
    const ssize_t n = ::read(fds[0], &c, 1);
    if (n <= 0 || c == '\n')
      break;
    number.push_back(c);
  }
  ::close(fds[0]);
  if (number.empty()) {
    ::close(life[1]); // the keeper stops Xvfb and exits with its status
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
      throw std::runtime_error(
          "cannot render: DISPLAY is unset and Xvfb is not installed (apt-get install xvfb)");
    throw std::runtime_error("cannot render: DISPLAY is unset and Xvfb did not start");
  }
  const std::string name = ":" + number;
  ::setenv("DISPLAY", name.c_str(), 1);
  return std::unique_ptr<VirtualDisplay>(new VirtualDisplay(pid, life[1], name));
}

void VirtualDisplay::Ensure() {
  static std::mutex m;
  static std::unique_ptr<VirtualDisplay> display;
  std::lock_guard<std::mutex> lock(m);
  if (!display)
    display = Start();
}

VirtualDisplay::~VirtualDisplay() {
  ::close(LifeFd_); // the keeper stops Xvfb and exits
  int status = 0;
  ::waitpid(Pid_, &status, 0);
  ::unsetenv("DISPLAY");
}

} // namespace bm
