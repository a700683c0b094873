// TestBmsimHostileCorpus.cxx - the hostile-input corpus run against bmsim (Docs/Reliability.md,
// "The corpus"): every reader of user files and every numeric option, given hostile values.
//
//   bmHostileCorpus BMSIM WORK_DIR options|files
//
// Each case writes its small input files (made here, no binary blobs) into WORK_DIR/case-N/in,
// runs bmsim in WORK_DIR/case-N/out and asserts: exit status 1 or 2 (no signal), every needle of
// the case in stderr (the option, field or file and the problem), nothing in the output folder
// (no output and no temporary file), the input folder as it was, and the run within kTimeBoundS.
// Cases run two at a time; the count of cases is printed. Exit status 0 when every case passed.
#include "bmHostileCorpus.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace bmcorpus {

std::string gBmsim;
fs::path gWork;
fs::path gBase;
std::vector<Case> gCases;

void Add(std::string name, std::vector<std::string> args, std::vector<std::string> needles,
         std::function<void(const fs::path&)> make) {
  gCases.push_back({std::move(name), std::move(args), std::move(needles), std::move(make)});
}

std::string Format(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

std::function<void(const fs::path&)> Writes(const std::string& name, const std::string& bytes) {
  return [=](const fs::path& in) { bmtest::WriteFile(in / name, bytes); };
}

} // namespace bmcorpus

using namespace bmcorpus;
using namespace bmtest;

namespace {

constexpr double kTimeBoundS = 20; ///< the longest a refusal may take, s

// ---------------------------------------------------------------------------------------------
// Running a case.

struct Result {
  bool ok = true;
  std::string why;
  double seconds = 0;
};

std::set<std::string> Listing(const fs::path& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec))
    names.insert(fs::relative(it->path(), dir).string());
  return names;
}

Result RunCase(const Case& c, size_t index) {
  Result r;
  const fs::path folder = gWork / ("case-" + std::to_string(index));
  const fs::path in = folder / "in", out = folder / "out";
  fs::remove_all(folder);
  fs::create_directories(in);
  fs::create_directories(out);
  try {
    if (c.make)
      c.make(in);
  } catch (const std::exception& e) {
    return {false, std::string("making the input: ") + e.what(), 0};
  }
  const auto inBefore = Listing(in);
  std::vector<std::string> args = {gBmsim};
  for (std::string a : c.args) {
    for (const auto& [key, value] :
         {std::pair<std::string, std::string>{"{in}", in.string()}, {"{out}", out.string()}})
      for (size_t at = a.find(key); at != std::string::npos; at = a.find(key))
        a.replace(at, key.size(), value);
    args.push_back(a);
  }
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string errPath = (folder / "stderr").string();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    if (::chdir(out.c_str()) != 0)
      ::_exit(127);
    const int devnull = ::open("/dev/null", O_RDWR);
    const int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(devnull, 0);
    ::dup2(devnull, 1);
    ::dup2(err, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  bool timedOut = false;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (r.seconds > kTimeBoundS) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      timedOut = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string err = ReadFile(errPath);
  fs::remove(errPath);
  std::ostringstream why;
  if (timedOut)
    why << "ran past " << kTimeBoundS << " s; ";
  else if (WIFSIGNALED(status))
    why << "killed by signal " << WTERMSIG(status) << " (" << ::strsignal(WTERMSIG(status))
        << "); ";
  else if (WEXITSTATUS(status) != 1 && WEXITSTATUS(status) != 2)
    why << "exit " << WEXITSTATUS(status) << ", expected 1 or 2; ";
  for (const auto& n : c.needles)
    if (err.find(n) == std::string::npos)
      why << "the message does not say '" << n << "'; ";
  const auto left = Listing(out);
  if (!left.empty())
    why << "left " << left.size() << " files, e.g. " << *left.begin() << "; ";
  const auto inAfter = Listing(in);
  for (const auto& f : inAfter)
    if (!inBefore.count(f))
      why << "wrote " << f << " beside the input; ";
  r.why = why.str();
  r.ok = r.why.empty();
  if (!r.ok)
    r.why += "stderr: " + err.substr(0, 600);
  if (r.ok)
    fs::remove_all(folder);
  return r;
}

/// Valid inputs the file cases damage: a DICOM series and an HDF5 recording made by bmsim.

} // namespace

int main(int argc, char** argv) {
  if (argc != 4 || (std::string(argv[3]) != "options" && std::string(argv[3]) != "files")) {
    std::cerr << "usage: bmHostileCorpus BMSIM WORK_DIR options|files\n";
    return 2;
  }
  gBmsim = fs::absolute(argv[1]).string();
  gWork = fs::absolute(argv[2]) / argv[3];
  gBase = gWork / "base";
  fs::remove_all(gWork);
  fs::create_directories(gWork);
  const std::string group = argv[3];
  if (group == "options") {
    OptionCases();
  } else {
    if (!MakeBase())
      return 1;
    FileCases();
  }
  std::atomic<size_t> next{0};
  std::mutex mutex;
  size_t failed = 0;
  double slowest = 0;
  std::string slowestName;
  const auto start = std::chrono::steady_clock::now();
  auto worker = [&] {
    for (size_t i = next++; i < gCases.size(); i = next++) {
      const Result r = RunCase(gCases[i], i);
      std::lock_guard<std::mutex> lock(mutex);
      if (r.seconds > slowest) {
        slowest = r.seconds;
        slowestName = gCases[i].name;
      }
      if (!r.ok) {
        ++failed;
        std::cout << "FAIL " << gCases[i].name << ": " << r.why << "\n";
      }
    }
  };
  std::thread second(worker);
  worker();
  second.join();
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "hostile corpus (" << group << "): " << gCases.size() << " cases, "
            << gCases.size() - failed << " refused as expected, " << failed << " failed; " << total
            << " s in all, slowest " << slowest << " s (" << slowestName << ")\n";
  if (failed == 0)
    fs::remove_all(gWork);
  return failed == 0 ? 0 : 1;
}
