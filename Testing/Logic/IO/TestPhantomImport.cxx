// Phantom -> DICOM series -> import -> voxmap: the bone volume matches the analytic one.
#include "bmImport.h"
#include "bmPhantom.h"
#include "bmVoxmapFile.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <random>

namespace fs = std::filesystem;

namespace {

fs::path TempDir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("bmio-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

} // namespace

TEST(Phantom, AnalyticVolumeMatchesQuadrature) {
  // Monte Carlo over the analytic box: independent check of the closed form (1 % at 2e6 points).
  for (const std::string name : {"glenoid", "block"}) {
    bm::PhantomInfo info = bm::GetPhantomInfo(name);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    const int n = 2000000;
    int hits = 0;
    double boxVol = 1;
    for (int a = 0; a < 3; ++a)
      boxVol *= info.boneBounds.hi[a] - info.boneBounds.lo[a] + 2.0;
    for (int i = 0; i < n; ++i) {
      std::array<double, 3> p;
      for (int a = 0; a < 3; ++a)
        p[a] = info.boneBounds.lo[a] - 1.0 +
               U(rng) * (info.boneBounds.hi[a] - info.boneBounds.lo[a] + 2.0);
      hits += bm::PhantomIsBone(name, p);
    }
    double mc = boxVol * hits / n;
    EXPECT_NEAR(mc, info.boneVolumeMm3, 0.01 * info.boneVolumeMm3) << name;
  }
  EXPECT_DOUBLE_EQ(bm::GetPhantomInfo("block").boneVolumeMm3, 144.0);
}

TEST(Phantom, GlenoidDicomImportVolumeWithinOnePercent) {
  fs::path dir = TempDir("glenoid");
  bm::PhantomInfo info = bm::WritePhantomSeries("glenoid", (dir / "P").string());
  ASSERT_TRUE(fs::is_directory(dir / "P"));
  bm::ImportOptions opt;
  opt.resolution = 128;
  bm::ImportResult r = bm::ImportToFile((dir / "P").string(), (dir / "v.nrrd").string(), opt);
  EXPECT_EQ(r.modality, "CT");
  EXPECT_EQ(r.format, "DICOM");
  double vol = r.voxmap.BoneVolume();
  std::cout << "glenoid analytic " << info.boneVolumeMm3 << " mm^3, CT " << r.segmentedVolumeMm3
            << ", voxmap " << vol << "\n"
            << r.Report();
  EXPECT_NEAR(vol, info.boneVolumeMm3, 0.01 * info.boneVolumeMm3);
  EXPECT_NEAR(r.segmentedVolumeMm3, info.boneVolumeMm3, 0.01 * info.boneVolumeMm3);
  // Placement in world mm: the voxmap's half-full voxels span the analytic bone box within a CT
  // voxel's partial-volume blur (0.5 mm) plus one voxmap voxel.
  const auto& vm = r.voxmap;
  std::array<int, 3> lo{1 << 30, 1 << 30, 1 << 30}, hi{-1, -1, -1};
  for (int k = 0; k < vm.Dims()[2]; ++k)
    for (int j = 0; j < vm.Dims()[1]; ++j)
      for (int i = 0; i < vm.Dims()[0]; ++i)
        if (vm.GetFill(vm.Index(i, j, k)) >= bm::Voxmap::kFull / 2) {
          std::array<int, 3> ijk{i, j, k};
          for (int a = 0; a < 3; ++a)
            lo[a] = std::min(lo[a], ijk[a]), hi[a] = std::max(hi[a], ijk[a]);
        }
  for (int a = 0; a < 3; ++a) {
    double wlo = vm.Origin()[a] + (lo[a] - 0.5) * vm.Spacing(),
           whi = vm.Origin()[a] + (hi[a] + 0.5) * vm.Spacing();
    EXPECT_NEAR(wlo, info.boneBounds.lo[a], 0.25 + vm.Spacing()) << "axis " << a;
    EXPECT_NEAR(whi, info.boneBounds.hi[a], 0.25 + vm.Spacing()) << "axis " << a;
  }
  // The pilot hole is empty, the vault behind it is bone (cancellous: material scale < 1).
  const auto& c = info.centreMm;
  const auto& n = info.axisOut;
  std::array<int, 3> ijk;
  ASSERT_TRUE(r.voxmap.VoxelAt({c[0] - 5 * n[0], c[1] - 5 * n[1], c[2] - 5 * n[2]}, ijk));
  EXPECT_EQ(r.voxmap.GetFill(r.voxmap.Index(ijk[0], ijk[1], ijk[2])), 0);
  ASSERT_TRUE(r.voxmap.VoxelAt({c[0] - 15 * n[0], c[1] - 15 * n[1], c[2] - 15 * n[2]}, ijk));
  auto idx = r.voxmap.Index(ijk[0], ijk[1], ijk[2]);
  EXPECT_EQ(r.voxmap.GetFill(idx), bm::Voxmap::kFull);
  EXPECT_NEAR(r.voxmap.Material(idx), 300.0 / 1200.0, 0.05);
  bm::Voxmap back = bm::LoadVoxmap((dir / "v.nrrd").string());
  EXPECT_TRUE(back == r.voxmap);
  fs::remove_all(dir);
}

// A disk that fills while the series is written (simulated by the file size limit, with
// SIGXFSZ ignored: each write past it fails as on a full disk): GDCM asserts (aborts) when its
// own output stream fails, so the writer must refuse with a message and leave nothing, not
// abort. Run in a child process: an abort there is the failure this test looks for.
TEST(Phantom, FullDiskIsRefusedWithoutAbortOrLeftovers) {
  const fs::path d = TempDir("fulldisk");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    signal(SIGXFSZ, SIG_IGN);
    rlimit lim{1000, 1000}; // bytes per file: less than one slice
    setrlimit(RLIMIT_FSIZE, &lim);
    int code = 3; // no refusal
    try {
      bm::WritePhantomSeries("block", (d / "ct").string());
    } catch (const std::runtime_error& e) {
      code = std::string(e.what()).find("cannot write") != std::string::npos ? 0 : 4;
    }
    if (code == 0 && !fs::is_empty(d))
      code = 5; // something left behind
    _exit(code);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_FALSE(WIFSIGNALED(status)) << "the writer died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "3: written, 4: another message, 5: leftovers";
  fs::remove_all(d);
}
