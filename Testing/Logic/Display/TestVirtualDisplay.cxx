// The private Xvfb of bm::VirtualDisplay dies with the process that started it, however that
// process ends (Docs/Reliability.md, "Temporary files"): SIGKILL included.
#include "bmVirtualDisplay.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <sstream>
#include <vector>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

namespace {

/// Whether process `pid` still runs (a zombie waiting for its reaper has ended).
bool Running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line))
    return false;
  const size_t close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] != 'Z';
}

bool XvfbInstalled() {
  return std::system("command -v Xvfb > /dev/null 2>&1") == 0;
}

/// The Xvfb started by a process of the tree under `root` (0: none), from /proc.
pid_t XvfbUnder(pid_t root) {
  std::map<pid_t, pid_t> parent;
  std::vector<pid_t> xvfbs;
  for (const auto& e : std::filesystem::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos)
      continue;
    std::ifstream stat(e.path() / "stat");
    std::string line;
    if (!std::getline(stat, line))
      continue;
    const size_t open = line.find('('), close = line.rfind(')');
    if (open == std::string::npos || close == std::string::npos)
      continue;
    std::istringstream rest(line.substr(close + 2));
    char state = 0;
    pid_t ppid = 0;
    rest >> state >> ppid;
    const pid_t pid = pid_t(std::stol(name));
    parent[pid] = ppid;
    if (line.substr(open + 1, close - open - 1) == "Xvfb" && state != 'Z')
      xvfbs.push_back(pid);
  }
  for (pid_t x : xvfbs)
    for (pid_t p = x; p > 1 && parent.count(p); p = parent[p])
      if (p == root)
        return x;
  return 0;
}

/// A child process that starts a private Xvfb and waits (killed when the test ends).
struct ChildWithDisplay {
  pid_t pid = 0;
  bool started = false;
  ChildWithDisplay() {
    int fds[2];
    if (::pipe(fds) != 0)
      return;
    pid = ::fork();
    if (pid == 0) {
      ::close(fds[0]);
      ::unsetenv("DISPLAY");
      char ok = 'n';
      try {
        static auto display = bm::VirtualDisplay::Start(20);
        ok = display ? 'y' : 'n';
      } catch (const std::exception&) {
      }
      if (::write(fds[1], &ok, 1) < 0)
        ::_exit(1);
      for (;;)
        ::pause();
    }
    ::close(fds[1]);
    char ok = 0;
    started = ::read(fds[0], &ok, 1) == 1 && ok == 'y';
    ::close(fds[0]);
  }
  ~ChildWithDisplay() {
    if (pid > 0 && ::kill(pid, SIGKILL) == 0)
      ::waitpid(pid, nullptr, 0);
  }
};

bool EndsWithin(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (Running(pid)) {
    if (std::chrono::steady_clock::now() > end)
      return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

} // namespace

TEST(VirtualDisplay, XvfbDiesWhenItsParentIsKilled) {
  if (!XvfbInstalled())
    GTEST_SKIP() << "Xvfb is not installed";
  ChildWithDisplay child;
  ASSERT_TRUE(child.started) << "the child did not start an Xvfb";
  const pid_t xvfb = XvfbUnder(child.pid);
  ASSERT_GT(xvfb, 0) << "no Xvfb under the child";
  ASSERT_EQ(::kill(child.pid, SIGKILL), 0);
  int status = 0;
  ::waitpid(child.pid, &status, 0);
  child.pid = 0;
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  EXPECT_TRUE(EndsWithin(xvfb, 5)) << "Xvfb " << xvfb << " outlived its parent";
}

TEST(VirtualDisplay, XvfbStopsWhenTheDisplayIsDestroyed) {
  if (!XvfbInstalled())
    GTEST_SKIP() << "Xvfb is not installed";
  const char* before = std::getenv("DISPLAY");
  const std::string saved = before ? before : "";
  ::unsetenv("DISPLAY");
  auto display = bm::VirtualDisplay::Start(20);
  ASSERT_TRUE(display);
  const pid_t xvfb = XvfbUnder(::getpid());
  ASSERT_GT(xvfb, 0);
  display.reset();
  EXPECT_TRUE(EndsWithin(xvfb, 5));
  EXPECT_EQ(std::getenv("DISPLAY"), nullptr);
  if (!saved.empty())
    ::setenv("DISPLAY", saved.c_str(), 1);
}
