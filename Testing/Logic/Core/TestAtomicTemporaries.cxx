// Temporaries of the atomic writer (bmAtomicFile.h) that killed runs left behind are removed the
// next time a run writes into that folder; a running writer's temporaries are kept.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <utime.h>

#include <filesystem>
#include <fstream>

#include "bmAtomicFile.h"

namespace {

namespace fs = std::filesystem;

struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("bm_atomic_tmp_" + std::to_string(::getpid()));
  ScratchDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  void Touch(const std::string& name, const std::string& text = "x") const {
    std::ofstream(path / name) << text;
  }
};

// The PID of a process that has ended (a child, reaped).
long DeadPid() {
  const pid_t pid = ::fork();
  if (pid == 0)
    ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return long(pid);
}

TEST(AtomicTemporaries, TheirNamesAreRecognised) {
  long pid = 0;
  const std::string name = fs::path(bm::TemporarySibling("/tmp/out/voxmap.nrrd")).filename();
  ASSERT_TRUE(bm::IsTemporaryName(name, pid)) << name;
  EXPECT_EQ(pid, long(::getpid()));
  EXPECT_TRUE(bm::IsTemporaryName(".summary.tmp-12-0", pid));
  EXPECT_EQ(pid, 12);
  EXPECT_TRUE(bm::IsTemporaryName(".a.b.tmp-7-3.csv", pid));
  EXPECT_EQ(pid, 7);
  for (const char* other : {"summary.tmp-12-0.json", ".hidden", ".x.tmp-12", ".x.tmp--1-2",
                            ".x.tmp-12-", ".x.tmp-12-3x", ".tmp-12-3", "report.html"})
    EXPECT_FALSE(bm::IsTemporaryName(other, pid)) << other;
}

TEST(AtomicTemporaries, StaleOnesAreRemovedLiveOnesKept) {
  ScratchDir d;
  const long dead = DeadPid();
  const std::string deadFile = ".voxmap.tmp-" + std::to_string(dead) + "-0.nrrd";
  const std::string deadFolder = ".series.d.tmp-" + std::to_string(dead) + "-1";
  const std::string reused = ".replay.tmp-1-4.csv"; // PID 1 started long after 1970
  const std::string live = ".summary.tmp-" + std::to_string(::getppid()) + "-2.json";
  d.Touch(deadFile);
  fs::create_directories(d.path / deadFolder);
  d.Touch(deadFolder + "/slice-001.dcm");
  d.Touch(reused);
  utimbuf epoch{0, 0};
  ASSERT_EQ(::utime((d.path / reused).c_str(), &epoch), 0);
  d.Touch(live);
  d.Touch(".hidden");
  d.Touch("result.csv");
  EXPECT_EQ(bm::RemoveStaleTemporaries(d.path.string()), 3);
  EXPECT_FALSE(fs::exists(d.path / deadFile));
  EXPECT_FALSE(fs::exists(d.path / deadFolder));
  EXPECT_FALSE(fs::exists(d.path / reused));
  EXPECT_TRUE(fs::exists(d.path / live)); // its writer (the parent process) still runs
  EXPECT_TRUE(fs::exists(d.path / ".hidden"));
  EXPECT_TRUE(fs::exists(d.path / "result.csv"));
  EXPECT_EQ(bm::RemoveStaleTemporaries((d.path / "missing").string()), 0);
}

TEST(AtomicTemporaries, TheFirstWriteIntoAFolderCleansIt) {
  ScratchDir d;
  const std::string left = ".summary.tmp-" + std::to_string(DeadPid()) + "-0.json";
  d.Touch(left, std::string(1000, 'x'));
  bm::WriteFileAtomic((d.path / "summary.json").string(), "{}");
  EXPECT_FALSE(fs::exists(d.path / left));
  EXPECT_TRUE(fs::exists(d.path / "summary.json"));
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(d.path))
    names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"summary.json"});
}

} // namespace
