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
#include <sys/wait.h>
#include <unistd.h>

namespace bm {

std::unique_ptr<VirtualDisplay> VirtualDisplay::Start(double timeoutS) {
  const char* d = std::getenv("DISPLAY");
  if (d && *d)
    return nullptr;
  int fds[2];
  if (::pipe(fds) != 0)
    throw std::runtime_error(std::string("cannot start Xvfb: pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string("cannot start Xvfb: fork: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::close(fds[0]);
    const std::string fd = std::to_string(fds[1]);
    // Keep Xvfb's chatter off the terminal.
    if (int null = ::open("/dev/null", O_WRONLY); null >= 0) {
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
    }
    ::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten",
             "tcp", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(fds[1]);
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
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
      throw std::runtime_error(
          "cannot render: DISPLAY is unset and Xvfb is not installed (apt-get install xvfb)");
    throw std::runtime_error("cannot render: DISPLAY is unset and Xvfb did not start");
  }
  const std::string name = ":" + number;
  ::setenv("DISPLAY", name.c_str(), 1);
  return std::unique_ptr<VirtualDisplay>(new VirtualDisplay(pid, name));
}

void VirtualDisplay::Ensure() {
  static std::mutex m;
  static std::unique_ptr<VirtualDisplay> display;
  std::lock_guard<std::mutex> lock(m);
  if (!display)
    display = Start();
}

VirtualDisplay::~VirtualDisplay() {
  ::kill(Pid_, SIGTERM);
  int status = 0;
  ::waitpid(Pid_, &status, 0);
  ::unsetenv("DISPLAY");
}

} // namespace bm
