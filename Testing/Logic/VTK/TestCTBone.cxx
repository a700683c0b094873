// vtkBMCTBoneSource: a CT's bone previewed at a threshold and region as a session would machine
// it (volume, bounds, suggested entry, bad input named), and a session on that bone from the
// suggested entry (vtkBMSessionSource BoneCT + OverrideTrial).
#include "vtkBMCTBoneSource.h"
#include "vtkBMSessionSource.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace fs = std::filesystem;

namespace {
/// A 4 x 4 x 3 mm cortical block (1600 HU; top face at z = 0, centred on the z axis) in air
/// (-1000 HU), 0.2 mm voxels, written as a plain-text NRRD CT.
fs::path WriteBlockCT(const fs::path& dir) {
  const fs::path path = dir / "block.nrrd";
  std::ofstream out(path);
  out << "NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\n"
         "sizes: 40 40 30\nspace directions: (0.2,0,0) (0,0.2,0) (0,0,0.2)\n"
         "kinds: domain domain domain\nencoding: ascii\nspace origin: (-3.9,-3.9,-4.9)\n\n";
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        const double x = -3.9 + 0.2 * i, y = -3.9 + 0.2 * j, z = -4.9 + 0.2 * k;
        const bool bone = x > -2 && x < 2 && y > -2 && y < 2 && z > -3 && z < 0;
        out << (bone ? 1600 : -1000) << "\n";
      }
  return path;
}

struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name)
      : dir(fs::temp_directory_path() / ("bm-ct-bone-" + name)) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
};
} // namespace

#ifdef BM_WITH_IO
TEST(CTBoneSource, PreviewsTheBoneAtThresholdAndRegion) {
  Scratch s("preview");
  const std::string ct = WriteBlockCT(s.dir).string();
  vtkNew<vtkBMCTBoneSource> source;
  source->SetFileName(ct.c_str());
  source->SetThresholdHU(500);
  source->SetResolution(48);
  source->Update();
  ASSERT_STREQ(source->GetLastError(), "");
  EXPECT_NEAR(source->GetBoneVolumeMm3(), 48.0, 2.5); // 4 x 4 x 3 mm
  EXPECT_GT(source->GetBoneVoxels(), 0);
  double* entry = source->GetSuggestedEntry();
  const double h = 4.0 / 48; // the voxmap's spacing: 48 cells over the 4 mm bone
  EXPECT_NEAR(entry[0], 0.0, h);
  EXPECT_NEAR(entry[1], 0.0, h);
  EXPECT_NEAR(entry[2], 0.0, 1.5 * h); // on the top face
  vtkImageData* image = source->GetOutput();
  ASSERT_NE(image->GetPointData()->GetArray("BoneFraction"), nullptr);
  EXPECT_GT(image->GetNumberOfPoints(), 48 * 48 * 30);
  // The extent is announced before data is requested (image consumers crop to it).
  int extent[6] = {0, -1, 0, -1, 0, -1}, dims[3];
  source->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  image->GetDimensions(dims);
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(extent[2 * a + 1] - extent[2 * a] + 1, dims[a]);

  // Half the block by the region of interest (x in [-2, 0]).
  source->SetROI(-5, 0, -5, 5, -5, 5);
  source->Update();
  ASSERT_STREQ(source->GetLastError(), "");
  EXPECT_NEAR(source->GetBoneVolumeMm3(), 24.0, 1.5);
  const std::string spec = source->GetBoneSpecification();
  EXPECT_NE(spec.find("\"roi\":[-5.0,-5.0,-5.0,0.0,5.0,5.0]"), std::string::npos) << spec;
  EXPECT_NE(spec.find("\"threshold\":500.0"), std::string::npos) << spec;

  // Bad input is named.
  source->SetROI(1, 0, -5, 5, -5, 5);
  source->Update();
  EXPECT_NE(std::string(source->GetLastError()).find("region of interest is empty"),
            std::string::npos);
  source->SetROI(0, 0, 0, 0, 0, 0);
  source->SetThresholdHU(3000); // above every voxel
  source->Update();
  EXPECT_STRNE(source->GetLastError(), "");
  EXPECT_EQ(source->GetBoneVoxels(), 0);
  source->SetFileName((s.dir / "missing.nrrd").string().c_str());
  source->SetThresholdHU(500);
  source->Update();
  EXPECT_NE(std::string(source->GetLastError()).find("missing.nrrd"), std::string::npos);
}

TEST(CTBoneSource, SessionMachinesTheCTBoneFromTheEntry) {
  Scratch s("session");
  const std::string ct = WriteBlockCT(s.dir).string();
  vtkNew<vtkBMCTBoneSource> preview;
  preview->SetFileName(ct.c_str());
  preview->SetThresholdHU(500);
  preview->SetAxis(0, 0, 1);
  preview->Update();
  ASSERT_STREQ(preview->GetLastError(), "");

  vtkNew<vtkBMSessionSource> session;
  session->SetScene("drilling"); // the reference drill, its feed and speed
  session->SetVoxmapResolution(64);
  session->SetShellResolution(128);
  session->RealTimeOff();
  session->SetMaxFrames(1500);
  session->SetBoneCT(preview->GetBoneSpecification());
  session->OverrideTrialOn();
  session->SetEntry(preview->GetSuggestedEntry());
  session->SetAxis(0, 0, 1);
  session->VolumeOutputOn();
  ASSERT_TRUE(session->Start()) << session->GetLastError();
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < end) {
    if (session->GetNeedsUpdate())
      session->Update();
    else if (session->GetState() == 2 || session->GetState() == 3)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(session->GetState(), 2); // paused at the frame limit
  EXPECT_GT(session->GetRemovedVolumeMm3(), 0.05) << "the drill cut none of the CT bone";
  // The session's bone is the CT block (4 mm wide), not the scene's 5 mm block.
  double b[6];
  session->GetBoneImage()->GetBounds(b);
  EXPECT_NEAR(b[1] - b[0], 4.0, 0.2);

  session->SetBoneFile(ct.c_str());
  EXPECT_FALSE(session->Start());
  EXPECT_NE(std::string(session->GetLastError()).find("not both"), std::string::npos);
}
#endif
