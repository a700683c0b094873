// A voxmap (also a cut one, with material) round-trips exactly through NRRD and MetaImage; saving
// is atomic.
#include "bmIOTestUtil.h"

#include "bmVoxmapFile.h"

#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <itkImageFileReader.h>
#include <itkNrrdImageIO.h>
#include <itkVectorImage.h>

using namespace bmtest;

namespace {

bm::Voxmap CutVoxmap() {
  // Odd spacing and origin that decimal text would not keep exactly.
  bm::Voxmap vm({37, 29, 23}, 0.1234567890123,
                {-60.123456789012345, 20.000000000000004, 1.0 / 3.0});
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> any(-bm::Voxmap::kFull, bm::Voxmap::kFull);
  std::uniform_real_distribution<float> mat(0.05f, 1.0f);
  for (int64_t v = 0; v < vm.NumVoxels(); ++v) {
    int kind = int(v % 5);
    vm.SetFill(v, kind == 0   ? 0
                  : kind == 1 ? bm::Voxmap::kFull
                              : any(rng)); // void, full, partial/over-cut
    vm.SetMaterial(v, kind == 2 ? 1.0f : mat(rng));
  }
  bool gone = false;
  vm.Remove(vm.Index(5, 5, 5), 123, gone);
  return vm;
}

} // namespace

TEST(VoxmapFile, RoundTripIsExact) {
  ScratchDir d("vmfile");
  bm::Voxmap vm = CutVoxmap();
  for (const char* name : {"v.nrrd", "v.mha"}) {
    bm::SaveVoxmap(vm, (d / name).string());
    bm::Voxmap back = bm::LoadVoxmap((d / name).string());
    EXPECT_TRUE(back == vm) << name;
    EXPECT_EQ(back.Spacing(), vm.Spacing()) << name;
    EXPECT_EQ(back.Origin(), vm.Origin()) << name;
    EXPECT_EQ(back.CountBone(), vm.CountBone()) << name;
    for (int64_t b = 0;
         b < int64_t(back.BrickDims()[0]) * back.BrickDims()[1] * back.BrickDims()[2]; ++b)
      ASSERT_EQ(back.BrickCount(b), vm.BrickCount(b));
  }
  EXPECT_EQ(d.Entries().size(), 2u); // no temporary left behind
}

TEST(VoxmapFile, TheTrialSavedWithTheBoneComesBackExactly) {
  ScratchDir d("vmtrial");
  const bm::Voxmap vm = CutVoxmap();
  const bm::VoxmapTrial trial{{-60.1, 20.000000000000004, 1.0 / 3.0},
                              {0.6, 0.0, 0.8},
                              R"({"type": "reamer", "radius_mm": 12.5, "name": "a = b := c"})"};
  for (const char* name : {"t.nrrd", "t.mha"}) {
    const std::string path = (d / name).string();
    bm::SaveVoxmap(vm, path, {}, bm::VoxmapTrialFields(trial));
    const std::optional<bm::VoxmapTrial> back = bm::LoadVoxmapTrial(path);
    ASSERT_TRUE(back.has_value()) << name;
    EXPECT_EQ(back->entryMm, trial.entryMm) << name;
    EXPECT_EQ(back->toolJson, trial.toolJson) << name;
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(back->axis[i], trial.axis[i], 1e-15) << name;
    EXPECT_TRUE(bm::LoadVoxmap(path) == vm) << name; // the voxels are unchanged
  }
  // A tool over several lines would break the header: refused before anything is written.
  EXPECT_THROW(bm::VoxmapTrialFields({{0, 0, 0}, {0, 0, 1}, "{\n}"}), std::invalid_argument);
  // None saved: none read.
  bm::SaveVoxmap(vm, (d / "plain.nrrd").string());
  EXPECT_FALSE(bm::LoadVoxmapTrial((d / "plain.nrrd").string()).has_value());
  // Half a trial, text, or a zero axis: refused, naming the file.
  const std::vector<std::vector<std::pair<std::string, std::string>>> bad = {
      {{"bm_trial_entry_mm", "0x1p+0 0x1p+0 0x1p+0"}},
      {{"bm_trial_entry_mm", "1 2"}, {"bm_trial_axis", "0 0 1"}},
      {{"bm_trial_entry_mm", "0 0 0"}, {"bm_trial_axis", "0 0 0"}},
      {{"bm_trial_entry_mm", "nan 0 0"}, {"bm_trial_axis", "0 0 1"}}};
  for (size_t i = 0; i < bad.size(); ++i) {
    const std::string path = (d / ("bad" + std::to_string(i) + ".nrrd")).string();
    bm::SaveVoxmap(vm, path, {}, bad[i]);
    try {
      bm::LoadVoxmapTrial(path);
      ADD_FAILURE() << "case " << i << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("trial"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(bm::LoadVoxmapTrial((d / "missing.nrrd").string()), std::runtime_error);
}

TEST(VoxmapFile, APaddedVoxmapIsWrittenVoxelByVoxel) {
  // 16 x 64 x 3 voxels: rows and slices padded in memory (Voxmap::Pitch), never in the file.
  ScratchDir d("vmfile5");
  bm::Voxmap vm({16, 64, 3}, 0.5, {0, 0, 0});
  ASSERT_GT(vm.StorageSize(), vm.NumVoxels());
  auto fillOf = [](int i, int j, int k) {
    return bm::Voxmap::Fill(((i + 16 * (j + 64 * k)) % 97 + 1) * (bm::Voxmap::kFull / 128));
  };
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 16; ++i)
        vm.SetFill(vm.Index(i, j, k), fillOf(i, j, k));
  vm.SetMaterial(vm.Index(3, 40, 2), 0.25f);
  const std::string path = (d / "v.nrrd").string();
  bm::SaveVoxmap(vm, path);
  using Image = itk::VectorImage<float, 3>;
  auto reader = itk::ImageFileReader<Image>::New();
  reader->SetImageIO(itk::NrrdImageIO::New());
  reader->SetFileName(path);
  reader->Update();
  const Image* img = reader->GetOutput();
  ASSERT_EQ(img->GetLargestPossibleRegion().GetSize()[0], 16u);
  ASSERT_EQ(img->GetLargestPossibleRegion().GetSize()[1], 64u);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 16; ++i) {
        const auto px = img->GetPixel({{i, j, k}});
        ASSERT_EQ(px[0], float(double(fillOf(i, j, k)) / bm::Voxmap::kFull)) << i << j << k;
        ASSERT_EQ(px[1], i == 3 && j == 40 && k == 2 ? 0.25f : 1.0f);
      }
  const bm::Voxmap back = bm::LoadVoxmap(path);
  EXPECT_TRUE(back == vm);
  EXPECT_EQ(back.CountBone(), 16 * 64 * 3);
}

TEST(VoxmapFile, WithoutMaterialLoadsAsCortical) {
  ScratchDir d("vmfile2");
  bm::Voxmap vm({8, 8, 8}, 0.5, {0, 0, 0});
  vm.SetFill(vm.Index(1, 2, 3), bm::Voxmap::kFull / 3);
  bm::SaveVoxmap(vm, (d / "v.nrrd").string());
  bm::Voxmap back = bm::LoadVoxmap((d / "v.nrrd").string());
  EXPECT_TRUE(back == vm);
  EXPECT_FALSE(back.HasMaterial());
}

TEST(VoxmapFile, RefusesBadTargetsAndWritesNothing) {
  ScratchDir d("vmfile3");
  bm::Voxmap vm({4, 4, 4}, 1.0, {0, 0, 0});
  EXPECT_THROW(bm::SaveVoxmap(vm, (d / "v.vtk").string()), std::runtime_error);
  EXPECT_THROW(bm::SaveVoxmap(vm, (d / "missing" / "v.nrrd").string()), std::runtime_error);
  EXPECT_TRUE(d.Entries().empty());
  EXPECT_THROW(bm::LoadVoxmap((d / "none.nrrd").string()), std::runtime_error);
}

TEST(VoxmapFile, CancelLeavesNoFile) {
  ScratchDir d("vmfile4");
  bm::Voxmap vm = CutVoxmap();
  bm::Progress cancel([](double f, const std::string&) { return f < 0.5; });
  EXPECT_THROW(bm::SaveVoxmap(vm, (d / "v.nrrd").string(), cancel), bm::Cancelled);
  EXPECT_TRUE(d.Entries().empty());
}
