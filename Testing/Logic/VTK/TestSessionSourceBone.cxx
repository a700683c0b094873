// vtkBMSessionSource: the panel's overrides (tool, force model, bone file, Touch), saving the cut
// bone and going on from it, the history and volume outputs, and bad input refused with a clear
// error before anything is written.
#include "vtkBMSessionSource.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#ifdef BM_WITH_IO
#include "bmVoxmapFile.h"
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>

namespace fs = std::filesystem;

namespace {
/// A short drilling session (64 / 128: coarse and fast), frames back to back.
void Configure(vtkBMSessionSource* s, vtkIdType frames) {
  s->SetScene("drilling");
  s->SetVoxmapResolution(64);
  s->SetShellResolution(128);
  s->RealTimeOff();
  s->SetMaxFrames(frames);
}

/// Polls the source as ParaView's live-source behaviour does until the session pauses.
bool RunToPause(vtkBMSessionSource* s, double timeoutS) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  while (std::chrono::steady_clock::now() < end) {
    if (s->GetNeedsUpdate())
      s->Update();
    else if (s->GetState() == 2 || s->GetState() == 3)
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// Bone volume of the source's Volume output, mm^3.
double ImageBoneVolume(vtkBMSessionSource* s) {
  vtkImageData* image = s->GetBoneImage();
  vtkDataArray* fraction = image->GetPointData()->GetArray("BoneFraction");
  if (!fraction)
    return -1;
  double sum = 0;
  for (vtkIdType i = 0; i < fraction->GetNumberOfTuples(); ++i)
    sum += fraction->GetTuple1(i);
  const double h = image->GetSpacing()[0];
  return sum * h * h * h;
}

/// Largest distance (mm) of the shown tool's points from the line along `axis` through their
/// mean: the tool's radius (its mesh is rings about its axis).
double ToolRadius(vtkBMSessionSource* s, const double axis[3]) {
  vtkPolyData* tool = vtkPolyData::SafeDownCast(s->GetOutputDataObject(1));
  const vtkIdType n = tool->GetNumberOfPoints();
  double mean[3] = {0, 0, 0};
  for (vtkIdType i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      mean[k] += tool->GetPoint(i)[k] / double(n);
  double radius = 0;
  for (vtkIdType i = 0; i < n; ++i) {
    double r[3], along = 0, r2 = 0;
    for (int k = 0; k < 3; ++k) {
      r[k] = tool->GetPoint(i)[k] - mean[k];
      along += r[k] * axis[k];
      r2 += r[k] * r[k];
    }
    radius = std::max(radius, std::sqrt(std::max(0.0, r2 - along * along)));
  }
  return radius;
}

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("bm-session-source-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}
} // namespace

#ifdef BM_WITH_IO
TEST(SessionSource, SavedBoneRoundTripsAndSessionsGoOnFromIt) {
  const fs::path dir = Scratch("roundtrip");
  const std::string file = (dir / "cut.nrrd").string();
  vtkNew<vtkBMSessionSource> s;
  Configure(s, 1500);
  s->VolumeOutputOn();
  ASSERT_TRUE(s->Start()) << s->GetLastError();
  ASSERT_TRUE(RunToPause(s, 120));
  EXPECT_STREQ(s->GetPauseReason(), "finished"); // the frame limit, not an overrun or a fault
  const double removed = s->GetRemovedVolumeMm3();
  EXPECT_GT(removed, 0.05) << "the drill cut no bone in 1.5 s";

  // History: one row per 10 ms of the 1.5 s ran, in time order.
  vtkTable* history = s->GetHistory();
  ASSERT_EQ(history->GetNumberOfColumns(), 6);
  EXPECT_NEAR(double(history->GetNumberOfRows()), 150.0, 2.0);
  vtkDataArray* time = vtkDataArray::SafeDownCast(history->GetColumnByName("time_s"));
  ASSERT_NE(time, nullptr);
  for (vtkIdType i = 1; i < time->GetNumberOfTuples(); ++i)
    ASSERT_GT(time->GetTuple1(i), time->GetTuple1(i - 1));
  ASSERT_NE(history->GetColumnByName("thrust_N"), nullptr);
  ASSERT_NE(history->GetColumnByName("feed_mm_per_rev"), nullptr);

  // Saving refuses a bad extension before writing anything.
  EXPECT_FALSE(s->SaveBone((dir / "cut.txt").string().c_str()));
  EXPECT_NE(std::string(s->GetLastError()).find(".nrrd or .mha"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "cut.txt"));

  ASSERT_TRUE(s->SaveBone(file.c_str())) << s->GetLastError();
  EXPECT_STREQ(s->GetLastError(), "");
  const double cut = ImageBoneVolume(s);
  // The volume port announces its grid before data is requested (ParaView's volume
  // representation crops to the announced extent: without it nothing is drawn).
  s->UpdateInformation();
  int extent[6] = {0, -1, 0, -1, 0, -1};
  s->GetOutputInformation(3)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  int dims[3];
  s->GetBoneImage()->GetDimensions(dims);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(extent[2 * a], 0);
    EXPECT_EQ(extent[2 * a + 1], dims[a] - 1);
  }
  const bm::Voxmap saved = bm::LoadVoxmap(file);
  EXPECT_NEAR(saved.BoneVolume(), cut, 1e-6 * cut);
  s->Stop();
  // Only the file remains in the folder (no temporary left over).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);

  // A fresh drilling bone holds the removed volume more than the saved one.
  vtkNew<vtkBMSessionSource> fresh;
  Configure(fresh, 1);
  fresh->VolumeOutputOn();
  ASSERT_TRUE(fresh->Start()) << fresh->GetLastError();
  ASSERT_TRUE(RunToPause(fresh, 60));
  EXPECT_NEAR(ImageBoneVolume(fresh) - cut, removed, 0.05 * removed + 1e-3);

  // Going on from the saved bone: the session starts on it, not on the scene's block.
  vtkNew<vtkBMSessionSource> again;
  Configure(again, 1);
  again->VolumeOutputOn();
  again->SetBoneFile(file.c_str());
  ASSERT_TRUE(again->Start()) << again->GetLastError();
  ASSERT_TRUE(RunToPause(again, 60));
  EXPECT_NEAR(ImageBoneVolume(again), cut, 1e-6 * cut);
  fs::remove_all(dir);
}

TEST(SessionSource, ASavedBoneGoesOnWhereItWasCut) {
  // A session cut at its own entry and axis (not the scene's); a start from its saved bone goes
  // on there, also in a new process (the trial is in the file), unless told otherwise.
  const fs::path dir = Scratch("trial");
  const std::string file = (dir / "cut.nrrd").string();
  vtkNew<vtkBMSessionSource> s;
  Configure(s, 200);
  ASSERT_TRUE(s->Start()) << s->GetLastError();
  double sceneEntry[3], sceneAxis[3];
  ASSERT_TRUE(s->GetSessionTrial(sceneEntry, sceneAxis));
  EXPECT_STREQ(s->GetSessionTrialSource(), "the scene's");
  s->Stop();
  const double entry[3] = {sceneEntry[0] + 3.25, sceneEntry[1] - 1.5, sceneEntry[2]};
  const double axis[3] = {0.2, 0.1, 1.0};               // not unit: the session normalises it
  s->SetTool(R"({"type": "drill", "radius_mm": 2.0})"); // the 4 mm drill, not the scene's 2.5 mm
  s->OverrideTrialOn();
  s->SetEntry(entry[0], entry[1], entry[2]);
  s->SetAxis(axis[0], axis[1], axis[2]);
  ASSERT_TRUE(s->Start()) << s->GetLastError();
  EXPECT_STREQ(s->GetSessionTrialSource(), "set");
  ASSERT_TRUE(RunToPause(s, 60));
  double cutEntry[3], cutAxis[3];
  ASSERT_TRUE(s->GetSessionTrial(cutEntry, cutAxis));
  ASSERT_TRUE(s->SaveBone(file.c_str())) << s->GetLastError();
  s->Stop();

  // The file carries the trial exactly (hexadecimal fields).
  const std::optional<bm::VoxmapTrial> saved = bm::LoadVoxmapTrial(file);
  ASSERT_TRUE(saved.has_value());
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(saved->entryMm[i], cutEntry[i]);
    EXPECT_EQ(saved->axis[i], cutAxis[i]);
  }

  EXPECT_NE(saved->toolJson.find("drill"), std::string::npos) << saved->toolJson;

  // Started again from the file: the saved trial, bit for bit, and the tool that cut it.
  vtkNew<vtkBMSessionSource> again;
  Configure(again, 1);
  again->SetBoneFile(file.c_str());
  ASSERT_TRUE(again->Start()) << again->GetLastError();
  EXPECT_STREQ(again->GetSessionTrialSource(), "the bone file's");
  ASSERT_TRUE(RunToPause(again, 60));
  EXPECT_NEAR(ToolRadius(again, cutAxis), 2.0, 1e-6); // the 4 mm drill that cut it
  double e[3], a[3];
  ASSERT_TRUE(again->GetSessionTrial(e, a));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(e[i], cutEntry[i]);
    EXPECT_NEAR(a[i], cutAxis[i], 1e-15);
  }
  again->Stop();

  // Told to keep the scene's trial (a plan's step scene), or given one: those win.
  again->BoneFileTrialOff();
  ASSERT_TRUE(again->Start()) << again->GetLastError();
  EXPECT_STREQ(again->GetSessionTrialSource(), "the scene's");
  ASSERT_TRUE(again->GetSessionTrial(e, a));
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(e[i], sceneEntry[i]);
  ASSERT_TRUE(RunToPause(again, 60));
  EXPECT_NEAR(ToolRadius(again, sceneAxis), 1.25, 1e-6); // the scene's 2.5 mm drill
  again->Stop();
  again->BoneFileTrialOn();
  again->OverrideTrialOn();
  again->SetEntry(sceneEntry);
  again->SetAxis(sceneAxis);
  ASSERT_TRUE(again->Start()) << again->GetLastError();
  EXPECT_STREQ(again->GetSessionTrialSource(), "set");
  again->Stop();

  // A voxmap saved without a trial (bmsim import's) starts at the scene's.
  const std::string plain = (dir / "plain.nrrd").string();
  bm::SaveVoxmap(bm::LoadVoxmap(file), plain);
  EXPECT_FALSE(bm::LoadVoxmapTrial(plain).has_value());
  vtkNew<vtkBMSessionSource> fromPlain;
  Configure(fromPlain, 1);
  fromPlain->SetBoneFile(plain.c_str());
  ASSERT_TRUE(fromPlain->Start()) << fromPlain->GetLastError();
  EXPECT_STREQ(fromPlain->GetSessionTrialSource(), "the scene's");
  fromPlain->Stop();
  fs::remove_all(dir);
}

TEST(SessionSource, MissingBoneFileIsRefused) {
  vtkNew<vtkBMSessionSource> s;
  Configure(s, 1);
  s->SetBoneFile("/nonexistent/cut.nrrd");
  EXPECT_FALSE(s->Start());
  EXPECT_NE(std::string(s->GetLastError()).find("/nonexistent/cut.nrrd"), std::string::npos);
}
#endif

TEST(SessionSource, SaveBoneNeedsASession) {
  const fs::path dir = Scratch("nosession");
  vtkNew<vtkBMSessionSource> s;
  EXPECT_TRUE(s->SaveBone("")); // clearing the property does nothing
  EXPECT_FALSE(s->SaveBone((dir / "cut.nrrd").string().c_str()));
  EXPECT_NE(std::string(s->GetLastError()).find("start a session first"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "cut.nrrd"));
  fs::remove_all(dir);
}

TEST(SessionSource, ToolAndMethodOverrideTheScene) {
  vtkNew<vtkBMSessionSource> s;
  Configure(s, 1);
  s->SetTool(R"({"type": "drill", "radius_mm": 2.0})");
  s->SetMethod(vtkBMSessionSource::ZHENG);
  ASSERT_TRUE(s->Start()) << s->GetLastError();
  ASSERT_TRUE(RunToPause(s, 60));
  double b[6];
  vtkPolyData::SafeDownCast(s->GetOutputDataObject(1))->GetBounds(b);
  EXPECT_NEAR(b[1] - b[0], 4.0, 1e-6); // the 4 mm drill, not the scene's 2.5 mm one
  s->Stop();

  s->SetTool(R"({"type": "drill", "point_angle_deg": 5})");
  EXPECT_FALSE(s->Start());
  EXPECT_NE(std::string(s->GetLastError()).find("point_angle_deg"), std::string::npos);
  s->SetTool("{not json");
  EXPECT_FALSE(s->Start());
  EXPECT_NE(std::string(s->GetLastError()).find("not JSON"), std::string::npos);
}

TEST(SessionSource, UnavailableTouchSaysWhy) {
  setenv("BM_LIBHD", "/nonexistent/libHD.so", 1);
  const std::string why = vtkBMSessionSource::ProbeTouch();
  EXPECT_NE(why.find("/nonexistent/libHD.so"), std::string::npos) << why;
  EXPECT_FALSE(why.empty());
  vtkNew<vtkBMSessionSource> s;
  Configure(s, 1);
  s->SetDeviceType(vtkBMSessionSource::TOUCH);
  EXPECT_FALSE(s->Start());
  EXPECT_NE(std::string(s->GetLastError()).find("/nonexistent/libHD.so"), std::string::npos);
  unsetenv("BM_LIBHD");
}

TEST(SessionSource, AVoxmapResolutionSetAloneScalesTheShellAlike) {
  // The drilling scene is 256 / 1024 (grids 2:1): voxmap 64 alone runs with shell 256; both set
  // run as set; neither keeps the scene's.
  vtkNew<vtkBMSessionSource> s;
  s->SetScene("drilling");
  s->RealTimeOff();
  s->SetMaxFrames(5);
  EXPECT_EQ(s->GetSessionShellResolution(), 0);
  s->SetVoxmapResolution(64);
  ASSERT_TRUE(s->Start()) << s->GetLastError();
  s->Stop();
  EXPECT_EQ(s->GetSessionVoxmapResolution(), 64);
  EXPECT_EQ(s->GetSessionShellResolution(), 256);
  s->SetShellResolution(128);
  ASSERT_TRUE(s->Start()) << s->GetLastError();
  s->Stop();
  EXPECT_EQ(s->GetSessionVoxmapResolution(), 64);
  EXPECT_EQ(s->GetSessionShellResolution(), 128);
}
