// The CT chain's segmentation stages (Docs/Segmentation.md): the voxmap keeps the segmented bone
// volume at any resolution, cavities are filled whatever they touch, touching bones are split by
// seeds, and the region of interest has one order and refuses an inverted box.
#include "bmImport.h"
#include "bmPhantom.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

namespace fs = std::filesystem;

namespace {

double Fill(const bm::Voxmap& v, const std::array<double, 3>& p) {
  std::array<int, 3> ijk;
  if (!v.VoxelAt(p, ijk))
    return -1;
  return v.Fraction(v.Index(ijk[0], ijk[1], ijk[2]));
}

/// A CT of `n` voxels of `spacing` mm (origin 0, identity direction) filled by hu(x, y, z).
template <class F> bm::CTImage MakeCT(std::array<size_t, 3> n, double spacing, F hu) {
  bm::CTImage ct;
  ct.hu = bm::HUImage::New();
  bm::HUImage::RegionType region;
  region.SetSize({{n[0], n[1], n[2]}});
  ct.hu->SetRegions(region);
  const double sp[3] = {spacing, spacing, spacing};
  ct.hu->SetSpacing(sp);
  ct.hu->Allocate();
  float* b = ct.hu->GetBufferPointer();
  for (size_t k = 0; k < n[2]; ++k)
    for (size_t j = 0; j < n[1]; ++j)
      for (size_t i = 0; i < n[0]; ++i)
        b[i + n[0] * (j + n[1] * k)] = float(hu(i * spacing, j * spacing, k * spacing));
  ct.source = "test";
  ct.format = "test";
  ct.modality = "CT";
  ct.huMin = -1000;
  ct.huMax = 1500;
  return ct;
}

} // namespace

TEST(Segmentation, VoxmapKeepsTheSegmentedVolumeOnEveryPhantom) {
  // CT voxels of 1 and 3 mm, voxmaps coarser and finer than the CT: within 3 % of the volume
  // segmented at the CT's own resolution.
  for (const std::string& name : bm::PhantomNames())
    for (double spacing : {1.0, 3.0})
      for (int resolution : {48, 160}) {
        bm::PhantomCTOptions ctOpt;
        ctOpt.inPlaneSpacingMm = ctOpt.sliceSpacingMm = spacing;
        ctOpt.supersample = 3;
        bm::ImportOptions opt;
        opt.resolution = resolution;
        bm::ImportResult r = bm::ImportVoxmap(bm::MakePhantomCT(name, ctOpt), opt);
        const double seg = r.segmentedVolumeMm3, vox = r.voxmap.BoneVolume();
        std::cout << name << " CT " << spacing << " mm, resolution " << resolution << ": segmented "
                  << seg << " mm^3, voxmap " << vox << " mm^3 (" << 100 * (vox / seg - 1)
                  << " %)\n";
        EXPECT_NEAR(vox, seg, 0.03 * seg) << name << " " << spacing << " mm " << resolution;
      }
}

TEST(Segmentation, RealHeadCTKeepsItsBoneVolumeAtEveryResolution) {
  const char* cranium = "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  if (!fs::exists(cranium))
    GTEST_SKIP() << "invesalius-examples is not installed";
  const bm::CTImage ct = bm::ReadCT(cranium);
  for (int resolution : {128, 256, 384}) {
    bm::ImportOptions opt;
    opt.resolution = resolution;
    bm::ImportResult r = bm::ImportVoxmap(ct, opt);
    const double seg = r.segmentedVolumeMm3, vox = r.voxmap.BoneVolume();
    std::cout << "Cranium.inv3 resolution " << resolution << " (" << r.voxmap.Spacing()
              << " mm): segmented " << seg << " mm^3, voxmap " << vox << " mm^3 ("
              << 100 * (vox / seg - 1) << " %)\n";
    EXPECT_NEAR(vox, seg, 0.03 * seg) << "resolution " << resolution;
  }
}

TEST(Segmentation, RegionOfInterestVolumeIsTheBoneInsideIt) {
  // The skull vault of the head CT cropped to the skull scene's 40 x 40 x 35 mm box: the volume
  // reported at the CT's resolution is the bone inside the box (not the crop's margin), and the
  // voxmap holds it.
  const char* cranium = "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  if (!fs::exists(cranium))
    GTEST_SKIP() << "invesalius-examples is not installed";
  bm::ImportOptions opt =
      bm::ImportOptionsFromJson({{"roi", {102.5, 85, 125, 142.5, 125, 160}}, {"resolution", 128}});
  bm::ImportResult r = bm::ImportVoxmap(cranium, opt);
  const double seg = r.segmentedVolumeMm3, vox = r.voxmap.BoneVolume();
  std::cout << "vault ROI: segmented " << seg << " mm^3, voxmap " << vox << " mm^3\n";
  EXPECT_NEAR(vox, seg, 0.03 * seg);
}

TEST(Segmentation, CavityCutOpenByTheImageBorderIsFilled) {
  // A hollow sphere (outer radius 12 mm, 2 mm cortical shell at 1500 HU, marrow 0 HU inside) in
  // soft tissue (40 HU), centred 5 mm above the image's bottom face: the border cuts the cavity
  // open. Filled, the bone is the whole truncated ball.
  const double R = 12, shell = 2, cz = 5.5; // centre (25, 25, cz) mm; the image starts at -0.5
  bm::CTImage ct = MakeCT({50, 50, 30}, 1.0, [&](double x, double y, double z) {
    const double r = std::sqrt((x - 25) * (x - 25) + (y - 25) * (y - 25) + (z - cz) * (z - cz));
    return r > R ? 40.0 : r > R - shell ? 1500.0 : 0.0;
  });
  // Ball truncated at z = -0.5 (h = cz + 0.5 below the centre): pi int (R^2 - t^2) dt.
  const double a = -(cz + 0.5), b = R;
  const double ball = std::numbers::pi * (R * R * (b - a) - (b * b * b - a * a * a) / 3);
  bm::ImportOptions opt;
  opt.resolution = 64;
  bm::ImportResult filled = bm::ImportVoxmap(ct, opt);
  std::cout << filled.Report();
  EXPECT_NEAR(filled.segmentedVolumeMm3, ball, 0.03 * ball);
  EXPECT_NEAR(filled.voxmap.BoneVolume(), ball, 0.04 * ball);
  EXPECT_EQ(Fill(filled.voxmap, {25, 25, cz}), 1.0); // the centre is bone
  EXPECT_EQ(Fill(filled.voxmap, {25, 25, 0}), 1.0);  // and the cut face too
  EXPECT_GE(filled.holesFilled, 1);

  opt.segmentation.fillHoles = false;
  bm::ImportResult shellOnly = bm::ImportVoxmap(ct, opt);
  EXPECT_LT(shellOnly.segmentedVolumeMm3, 0.6 * ball);
  EXPECT_EQ(Fill(shellOnly.voxmap, {25, 25, cz}), 0.0);
}

TEST(Segmentation, TheFillKeepsBonesApartWhenAllAreKept) {
  // Two hollow balls (outer radius 10 mm, 2 mm cortical shell at 1500 HU, marrow 0 HU) 2 mm apart
  // on 1 mm voxels, as a humeral head two voxels from the glenoid on a coarse scan: the closing
  // bridges the gap and encloses part of it. With every bone kept, each marrow is filled but the
  // gap is not: the bone is the two full balls, and the voxel between them stays empty.
  const double R = 10, shell = 2, gap = 2;
  const double c1 = 15, c2 = c1 + 2 * R + gap; // centres on x, y = z = 15 mm
  bm::CTImage ct = MakeCT({50, 30, 30}, 1.0, [&](double x, double y, double z) {
    double hu = 40;
    for (double c : {c1, c2}) {
      const double r = std::sqrt((x - c) * (x - c) + (y - 15) * (y - 15) + (z - 15) * (z - 15));
      if (r <= R)
        hu = r > R - shell ? 1500.0 : 0.0;
    }
    return hu;
  });
  const double ball = 4.0 / 3.0 * std::numbers::pi * R * R * R;
  bm::ImportOptions opt;
  opt.resolution = 100;
  opt.segmentation.keepAllComponents = true;
  const bm::ImportResult r = bm::ImportVoxmap(ct, opt);
  std::cout << r.Report();
  EXPECT_NEAR(r.segmentedVolumeMm3, 2 * ball, 0.05 * ball);
  EXPECT_EQ(Fill(r.voxmap, {c1, 15, 15}), 1.0); // each marrow filled
  EXPECT_EQ(Fill(r.voxmap, {c2, 15, 15}), 1.0);
  EXPECT_LT(Fill(r.voxmap, {c1 + R + 0.5 * gap, 15, 15}), 0.5); // the gap is not
}

TEST(Segmentation, MetalIsNamedAndLeftOutOfTheBone) {
  // A 20 mm cube of bone (1500 HU) holding a screw (a 2 mm radius, 14 mm cylinder at 4000 HU)
  // in soft tissue: the screw is not bone, is not filled back as a cavity, and is named.
  const double c = 20, half = 10, r = 2, len = 7;
  bm::CTImage ct = MakeCT({40, 40, 40}, 1.0, [&](double x, double y, double z) {
    if (std::hypot(x - c, y - c) <= r && std::abs(z - c) <= len)
      return 4000.0;
    return std::abs(x - c) <= half && std::abs(y - c) <= half && std::abs(z - c) <= half ? 1500.0
                                                                                         : 40.0;
  });
  bm::ImportOptions opt;
  opt.resolution = 80;
  const bm::ImportResult r1 = bm::ImportVoxmap(ct, opt);
  std::cout << r1.Report();
  // On the 1 mm grid the cube is 21^3 voxel centres; the screw's voxels come out of it.
  const double cube = std::pow(2 * half + 1, 3), screw = std::numbers::pi * r * r * 2 * len;
  EXPECT_NEAR(r1.voxmap.BoneVolume(), cube - screw, 0.5 * screw);
  EXPECT_LT(Fill(r1.voxmap, {c, c, c}), 0.5); // the screw's axis
  EXPECT_EQ(Fill(r1.voxmap, {c + 6, c, c}), 1.0);
  bool named = false;
  for (const auto& w : r1.warnings)
    named |= w.find("metal") != std::string::npos && w.find("(20, 20, 20)") != std::string::npos;
  EXPECT_TRUE(named) << r1.Report();
}

TEST(Segmentation, DrilledHoleOpenToTheSurroundingsStaysEmpty) {
  // A 3 mm hole drilled 8 mm into a cortical block from its top face: not a cavity.
  bm::CTImage ct = MakeCT({40, 40, 40}, 0.5, [](double x, double y, double z) {
    const bool block = x > 4 && x < 16 && y > 4 && y < 16 && z > 4 && z < 14;
    const bool hole = (x - 10) * (x - 10) + (y - 10) * (y - 10) < 1.5 * 1.5 && z > 6;
    return block && !hole ? 1500.0 : 40.0;
  });
  bm::ImportOptions opt;
  opt.resolution = 48;
  bm::ImportResult r = bm::ImportVoxmap(ct, opt);
  EXPECT_EQ(Fill(r.voxmap, {10, 10, 10}), 0.0);
  EXPECT_EQ(r.holesFilled, 0);
}

TEST(Segmentation, TouchingBonesAreSplitBySeeds) {
  // The shoulder phantom at 1 mm: the point spread joins the humeral head to the glenoid plate
  // across the 3.5 mm joint space at the bone threshold.
  bm::PhantomCTOptions ctOpt;
  ctOpt.inPlaneSpacingMm = ctOpt.sliceSpacingMm = 1.0;
  ctOpt.supersample = 3;
  const bm::CTImage ct = bm::MakePhantomCT("shoulder", ctOpt);
  const std::array<double, 3> plateCentre{-33.5, 0, 0}, headCentre{0, 0, 0};
  // Each bone alone, as the same CT segments it: the other side of the joint's mid-plane
  // (x = -23.75 mm) replaced by soft tissue (40 HU).
  auto alone = [&](bool plateSide) {
    bm::CTImage one = ct;
    auto copy = bm::HUImage::New();
    copy->CopyInformation(ct.hu);
    copy->SetRegions(ct.hu->GetLargestPossibleRegion());
    copy->Allocate();
    const auto n = ct.hu->GetLargestPossibleRegion().GetSize();
    const float* src = ct.hu->GetBufferPointer();
    float* dst = copy->GetBufferPointer();
    for (size_t k = 0; k < n[2]; ++k)
      for (size_t j = 0; j < n[1]; ++j)
        for (size_t i = 0; i < n[0]; ++i) {
          const size_t v = i + n[0] * (j + n[1] * k);
          const double x = ct.hu->GetOrigin()[0] + double(i) * ct.hu->GetSpacing()[0];
          dst[v] = (x < -23.75) == plateSide ? src[v] : 40.0f;
        }
    one.hu = copy;
    bm::ImportOptions o;
    o.resolution = 96;
    return bm::ImportVoxmap(one, o).segmentedVolumeMm3;
  };
  const double plate = alone(true), head = alone(false);
  bm::ImportOptions opt;
  opt.resolution = 96;
  opt.segmentation.seedMm = plateCentre;
  bm::ImportResult joined = bm::ImportVoxmap(ct, opt);
  std::cout << joined.Report() << "plate alone " << plate << " mm^3, head alone " << head
            << " mm^3\n";
  EXPECT_GT(joined.segmentedVolumeMm3, plate + 0.8 * head) << "the bones should touch";

  opt.segmentation.excludeSeedsMm = {headCentre};
  bm::ImportResult split = bm::ImportVoxmap(ct, opt);
  std::cout << split.Report();
  EXPECT_GT(split.separationDepthMm, 0);
  EXPECT_NEAR(split.segmentedVolumeMm3, plate, 0.05 * plate);
  EXPECT_NEAR(split.voxmap.BoneVolume(), plate, 0.05 * plate);
  EXPECT_EQ(Fill(split.voxmap, plateCentre), 1.0);
  EXPECT_LE(Fill(split.voxmap, headCentre), 0.0); // outside the voxmap or empty
  EXPECT_LT(split.roi.hi[0], -15.0);              // the voxmap ends at the joint

  // The other way round: the head kept, the plate dropped.
  opt.segmentation.seedMm = headCentre;
  opt.segmentation.excludeSeedsMm = {plateCentre};
  bm::ImportResult headOnly = bm::ImportVoxmap(ct, opt);
  EXPECT_NEAR(headOnly.segmentedVolumeMm3, head, 0.05 * head);
  EXPECT_GT(headOnly.roi.lo[0], -30.0);

  // A seed off the bone is named in a warning and ignored.
  opt.segmentation.excludeSeedsMm = {{0, 0, 30}}; // above the head, in soft tissue
  bm::ImportResult warned = bm::ImportVoxmap(ct, opt);
  ASSERT_FALSE(warned.warnings.empty());
  EXPECT_NE(warned.warnings.back().find("not on bone"), std::string::npos)
      << warned.warnings.back();
  EXPECT_NE(warned.Report().find("exclude seed (0, 0, 30) mm"), std::string::npos);
}

TEST(Segmentation, SeedsAndRegionFromSceneKeys) {
  nlohmann::json bone = {{"phantom", "shoulder"},  {"seed", {-33.5, 0, 0}},
                         {"exclude", {{0, 0, 0}}}, {"closingRadius", 0},
                         {"separationDepth", 6},   {"roi", {-45, -25, -35, 25, 25, 35}}};
  bm::ImportOptions o = bm::ImportOptionsFromJson(bone);
  ASSERT_EQ(o.segmentation.excludeSeedsMm.size(), 1u);
  EXPECT_EQ(o.segmentation.closingRadiusVoxels, 0);
  EXPECT_EQ(o.segmentation.separation.maxDepthMm, 6.0);
  ASSERT_TRUE(o.roiMm);
  EXPECT_EQ(o.roiMm->lo[1], -25.0);
  EXPECT_EQ(o.roiMm->hi[2], 35.0);
  // One ROI order (x0, y0, z0, x1, y1, z1); an inverted box is an error, not swapped.
  bone["roi"] = {-45, 25, -35, 25, -25, 35};
  try {
    bm::ImportOptionsFromJson(bone);
    FAIL() << "an inverted ROI was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("inverted or empty along y"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(bm::RoiFromCorners({0, 0, 0, 1, 1}, "--roi"), std::runtime_error);
  EXPECT_THROW(bm::ImportOptionsFromJson({{"exclude", {1, 2, 3}}}), std::runtime_error);
  const auto pts = bm::ParsePointsMm("1,2,3;-4,5.5,6", "--exclude");
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts[1][0], -4.0);
  EXPECT_EQ(pts[1][1], 5.5);
  EXPECT_THROW(bm::ParsePointsMm("1,2", "--exclude"), std::runtime_error);
  EXPECT_THROW(bm::ParsePointsMm("1,2,x", "--exclude"), std::runtime_error);
}

TEST(Segmentation, ImportSettingsRoundTripThroughSceneKeys) {
  // What a plan's step scenes carry (bmGlenoidPlan.h CtBoneJsonWithSettings) reads back as the
  // options it was written from.
  bm::ImportOptions o;
  o.read.intensity.rawThreshold = 102.5;
  o.read.seriesUID = "1.2.840.1";
  o.read.maxMemoryBytes = 512ull << 20;
  o.read.allowDataOutsideFolder = true;
  o.segmentation.excludeSeedsMm = {{1, 2, 3}, {-4, 5, 6}};
  o.segmentation.seedMm = std::array<double, 3>{7, 8, 9};
  o.segmentation.fillHoles = false;
  o.segmentation.keepAllComponents = true;
  o.roiMm = bm::RoiFromCorners({-1, -2, -3, 4, 5, 6}, "roi");
  bm::OrientedBox box;
  box.centreMm = {1, 2, 3};
  box.halfSizesMm = {10, 20, 30};
  box.rotationDeg = {0, 15, 0};
  o.segmentation.box = box;
  o.resolution = 96;
  const bm::ImportOptions back = bm::ImportOptionsFromJson(bm::ImportOptionsToJson(o));
  EXPECT_EQ(back.read.intensity.rawThreshold, 102.5);
  EXPECT_FALSE(back.read.intensity.huMapping);
  EXPECT_EQ(back.read.seriesUID, o.read.seriesUID);
  EXPECT_EQ(back.read.maxMemoryBytes, o.read.maxMemoryBytes);
  EXPECT_TRUE(back.read.allowDataOutsideFolder);
  EXPECT_EQ(back.segmentation.excludeSeedsMm, o.segmentation.excludeSeedsMm);
  EXPECT_EQ(back.segmentation.seedMm, o.segmentation.seedMm);
  EXPECT_FALSE(back.segmentation.fillHoles);
  EXPECT_TRUE(back.segmentation.keepAllComponents);
  ASSERT_TRUE(back.roiMm);
  EXPECT_EQ(back.roiMm->lo, o.roiMm->lo);
  EXPECT_EQ(back.roiMm->hi, o.roiMm->hi);
  ASSERT_TRUE(back.segmentation.box);
  EXPECT_EQ(back.segmentation.box->rotationDeg, box.rotationDeg);
  EXPECT_EQ(back.resolution, 96);
  // HU: the threshold and a mapping.
  bm::ImportOptions hu;
  hu.segmentation.thresholdHU = 250;
  hu.read.intensity.huMapping = std::array<double, 2>{7.84, -600};
  const bm::ImportOptions huBack = bm::ImportOptionsFromJson(bm::ImportOptionsToJson(hu));
  EXPECT_EQ(huBack.segmentation.thresholdHU, 250.0f);
  ASSERT_TRUE(huBack.read.intensity.huMapping);
  EXPECT_EQ((*huBack.read.intensity.huMapping)[0], 7.84);
  EXPECT_FALSE(huBack.read.intensity.rawThreshold);
}

TEST(Segmentation, OrientedBoxKeepsTheBoneInside) {
  // A 10 mm cortical cube (0.5 mm voxels) and a box turned 45 degrees about z, 4 mm thick along
  // (1, 1, 0), 40 mm along (-1, 1, 0): the bone kept is the cube's diagonal strip,
  // (100 - (10 - 2 sqrt 2)^2) mm^2 x 10 mm.
  bm::CTImage ct = MakeCT({40, 40, 40}, 0.5, [](double x, double y, double z) {
    return x > 5 && x < 15 && y > 5 && y < 15 && z > 5 && z < 15 ? 1500.0 : 40.0;
  });
  const double leg = 10 - 2 * std::sqrt(2.0);
  const double strip = (100 - leg * leg) * 10;
  nlohmann::json bone = {
      {"box", {{"centre", {10, 10, 10}}, {"halfSizes", {2, 20, 20}}, {"rotation", {0, 0, 45}}}},
      {"resolution", 64}};
  bm::ImportOptions opt = bm::ImportOptionsFromJson(bone);
  ASSERT_TRUE(opt.segmentation.box);
  bm::ImportResult r = bm::ImportVoxmap(ct, opt);
  std::cout << "oriented strip: analytic " << strip << " mm^3, segmented " << r.segmentedVolumeMm3
            << ", voxmap " << r.voxmap.BoneVolume() << "\n";
  EXPECT_NEAR(r.segmentedVolumeMm3, strip, 0.04 * strip);
  EXPECT_NEAR(r.voxmap.BoneVolume(), strip, 0.04 * strip);
  EXPECT_GT(Fill(r.voxmap, {10, 10, 10}), 0.99); // the centre: inside
  EXPECT_LE(Fill(r.voxmap, {13, 13, 10}), 0.0);  // on the cube, across the box's thin axis
  EXPECT_GT(Fill(r.voxmap, {13, 7, 10}), 0.99);  // on the cube, along the box

  const auto text = bm::OrientedBoxFromText("10,10,10,2,20,20,0,0,45", "--box");
  EXPECT_TRUE(text.Contains({13, 7, 10}));
  EXPECT_FALSE(text.Contains({13, 13, 10}));
  EXPECT_THROW(bm::OrientedBoxFromText("10,10,10,2,0,20", "--box"), std::runtime_error);
  EXPECT_THROW(bm::OrientedBoxFromText("10,10,10,2", "--box"), std::runtime_error);
  bone["box"]["halfSizes"] = {2, -1, 20};
  EXPECT_THROW(bm::ImportOptionsFromJson(bone), std::runtime_error);
}
