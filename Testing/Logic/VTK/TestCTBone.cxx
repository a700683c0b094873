// vtkBMCTBoneSource: a CT's bone previewed at a threshold and region as a session would machine
// it (volume, bounds, suggested entry, bad input named), and a session on that bone from the
// suggested entry (vtkBMSessionSource BoneCT + OverrideTrial).
#include "vtkBMCTBoneSource.h"
#ifdef BM_WITH_IO
#include "bmBoxROI.h"
#endif
#include "vtkBMSessionSource.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTransform.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
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

/// The same block CT as a vtkImageData in memory (HU as short point scalars).
vtkSmartPointer<vtkImageData> BlockImage() {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(40, 40, 30);
  image->SetSpacing(0.2, 0.2, 0.2);
  image->SetOrigin(-3.9, -3.9, -4.9);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        const double x = -3.9 + 0.2 * i, y = -3.9 + 0.2 * j, z = -4.9 + 0.2 * k;
        const bool bone = x > -2 && x < 2 && y > -2 && y < 2 && z > -3 && z < 0;
        *v++ = bone ? 1600 : -1000;
      }
  return image;
}

/// The block CT as a legacy VTK structured-points file (ASCII).
fs::path WriteBlockVTK(const fs::path& dir) {
  const fs::path path = dir / "block.vtk";
  std::ofstream out(path);
  out << "# vtk DataFile Version 3.0\nblock CT\nASCII\nDATASET STRUCTURED_POINTS\n"
         "DIMENSIONS 40 40 30\nORIGIN -3.9 -3.9 -4.9\nSPACING 0.2 0.2 0.2\n"
         "POINT_DATA 48000\nSCALARS HU short 1\nLOOKUP_TABLE default\n";
  vtkSmartPointer<vtkImageData> image = BlockImage();
  const auto* v = static_cast<const short*>(image->GetScalarPointer());
  for (int n = 0; n < 48000; ++n)
    out << v[n] << "\n";
  return path;
}

void CountProgress(vtkObject*, unsigned long, void* count, void*) {
  ++*static_cast<int*>(count);
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
  source->SetROI(-5, -5, -5, 0, 5, 5); // x0, y0, z0, x1, y1, z1
  source->Update();
  ASSERT_STREQ(source->GetLastError(), "");
  EXPECT_NEAR(source->GetBoneVolumeMm3(), 24.0, 1.5);
  const std::string spec = source->GetBoneSpecification();
  EXPECT_NE(spec.find("\"roi\":[-5.0,-5.0,-5.0,0.0,5.0,5.0]"), std::string::npos) << spec;
  EXPECT_NE(spec.find("\"threshold\":500.0"), std::string::npos) << spec;

  // Bad input is named.
  source->SetROI(1, -5, -5, 0, 5, 5); // inverted along x: an error, not swapped
  source->Update();
  EXPECT_NE(std::string(source->GetLastError()).find("region of interest is inverted"),
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

TEST(CTBoneSource, FiltersACTImageFromTheHostViewer) {
  // A CT any ParaView reader produced, fed in as the filter's (optional) input: the FileName is
  // not needed, the bone is the block's, progress is reported, and the bone specification names
  // a copy of the CT a session can import.
  vtkNew<vtkBMCTBoneSource> filter;
  vtkSmartPointer<vtkImageData> ct = BlockImage();
  filter->SetInputData(ct);
  filter->SetThresholdHU(500);
  filter->SetResolution(48);
  int progressEvents = 0;
  vtkNew<vtkCallbackCommand> onProgress;
  onProgress->SetCallback(CountProgress);
  onProgress->SetClientData(&progressEvents);
  filter->AddObserver(vtkCommand::ProgressEvent, onProgress);
  filter->Update();
  ASSERT_STREQ(filter->GetLastError(), "");
  EXPECT_NEAR(filter->GetBoneVolumeMm3(), 48.0, 2.5); // 4 x 4 x 3 mm
  EXPECT_GT(progressEvents, 3);
  const double* b = filter->GetBoneBounds();
  EXPECT_NEAR(b[1] - b[0], 4.2, 0.2); // 4 mm and half a CT voxel either side
  EXPECT_NEAR(0.5 * (b[4] + b[5]), -1.5, 0.15);
  const nlohmann::json spec = nlohmann::json::parse(filter->GetBoneSpecification());
  ASSERT_TRUE(spec.contains("ct")) << spec.dump();
  EXPECT_TRUE(fs::exists(spec["ct"].get<std::string>()));

  // A changed input is imported again: half the block (x > 0) set to soft tissue.
  auto* v = static_cast<short*>(ct->GetScalarPointer());
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 20; i < 40; ++i)
        v[i + 40 * (j + 40 * k)] = 40;
  ct->Modified();
  filter->Update();
  ASSERT_STREQ(filter->GetLastError(), "");
  EXPECT_NEAR(filter->GetBoneVolumeMm3(), 24.0, 1.5);

  // Seeds and the oriented box reach the import: a box holding the block's y < 0 half (turned
  // 90 degrees about z, its x axis along world y) keeps half of what is left (12 mm^3); an
  // exclude seed off the bone is ignored; the specification carries them for the session.
  filter->UseSeedOn();
  filter->SetSeed(-1, -1, -1.5);
  filter->AddExcludePoint(3, 3, 3); // in air
  filter->UseBoxOn();
  filter->SetBoxCentre(0, -2, -1.5);
  filter->SetBoxHalfSizes(2, 5, 5);
  filter->SetBoxRotation(0, 0, 90);
  filter->Update();
  ASSERT_STREQ(filter->GetLastError(), "");
  EXPECT_NEAR(filter->GetBoneVolumeMm3(), 12.0, 1.0);
  EXPECT_EQ(filter->GetNumberOfExcludePoints(), 1);
  const nlohmann::json seeded = nlohmann::json::parse(filter->GetBoneSpecification());
  EXPECT_EQ(seeded["exclude"].size(), 1u) << seeded.dump();
  EXPECT_EQ(seeded["box"]["rotation"][2].get<double>(), 90.0) << seeded.dump();
  EXPECT_EQ(seeded["seed"][0].get<double>(), -1.0) << seeded.dump();
  filter->UseBoxOff();
  filter->UseSeedOff();
  filter->RemoveAllExcludePoints();

  // An image with no values is named.
  vtkNew<vtkImageData> empty;
  empty->SetDimensions(4, 4, 4);
  filter->SetInputData(empty);
  filter->Update();
  EXPECT_NE(std::string(filter->GetLastError()).find("no point scalars"), std::string::npos)
      << filter->GetLastError();
}

// ParaView's box widget (Position, Rotation, Scale on a reference box) and the import's oriented
// box describe the same box: the rotation order is VTK's (y, then x, then z), and the reference
// box's scale and offset become the centre and half sizes.
TEST(CTBoneSource, BoxWidgetIsTheBoxThatIsCut) {
  bm::OrientedBox box;
  box.rotationDeg = {20, 35, -50};
  vtkNew<vtkTransform> widget;
  widget->RotateZ(-50);
  widget->RotateX(20);
  widget->RotateY(35);
  const auto axes = box.Axes();
  for (int a = 0; a < 3; ++a)
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(axes[a][r], widget->GetMatrix()->GetElement(r, a), 1e-12) << a << r;

  vtkNew<vtkBMCTBoneSource> filter;
  filter->SetFileName("ct.nrrd"); // the specification is built, nothing is read
  filter->UseBoxOn();
  filter->SetBoxCentre(1, 2, 3);
  filter->SetBoxHalfSizes(2, 4, 6); // the widget's scale
  filter->SetBoxRotation(0, 0, 90);
  nlohmann::json spec = nlohmann::json::parse(filter->GetBoneSpecification());
  for (int a = 0; a < 3; ++a) // default reference [-1, 1]^3: centre and half sizes as given
    EXPECT_NEAR(spec["box"]["centre"][a].get<double>(), (std::array{1., 2., 3.})[a], 1e-12);
  filter->SetBoxUseReferenceBounds(false); // the unit cube: the position is a corner
  spec = nlohmann::json::parse(filter->GetBoneSpecification());
  const std::array<double, 3> centre{1 - 2, 2 + 1, 3 + 3}, half{1, 2, 3}; // + Rz(90) (1, 2, 3)
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(spec["box"]["centre"][a].get<double>(), centre[a], 1e-12) << spec.dump();
    EXPECT_NEAR(spec["box"]["halfSizes"][a].get<double>(), half[a], 1e-12) << spec.dump();
  }
  filter->SetBoxUseReferenceBounds(true);
  filter->SetBoxReferenceBounds(0, 0, -1, 1, -1, 1);
  EXPECT_STREQ(filter->GetBoneSpecification(), "");
  filter->Update();
  EXPECT_NE(std::string(filter->GetLastError()).find("reference bounds are empty"),
            std::string::npos)
      << filter->GetLastError();
}

TEST(CTBoneSource, ReadsAVTKImageFile) {
  Scratch s("vtk-file");
  const std::string path = WriteBlockVTK(s.dir).string();
  vtkNew<vtkBMCTBoneSource> source;
  source->SetFileName(path.c_str());
  source->SetThresholdHU(500);
  source->SetResolution(48);
  source->Update();
  ASSERT_STREQ(source->GetLastError(), "");
  EXPECT_NEAR(source->GetBoneVolumeMm3(), 48.0, 2.5);
  source->SetFileName((s.dir / "missing.vti").string().c_str());
  source->Update();
  EXPECT_NE(std::string(source->GetLastError()).find("missing.vti"), std::string::npos);
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
  // The session's bone is the CT block (4 mm wide, its voxmap covering half a CT voxel more on
  // each side: 4.2 mm), not the scene's 5 mm block.
  double b[6];
  session->GetBoneImage()->GetBounds(b);
  EXPECT_NEAR(b[1] - b[0], 4.2, 0.2);

  session->SetBoneFile(ct.c_str());
  EXPECT_FALSE(session->Start());
  EXPECT_NE(std::string(session->GetLastError()).find("not both"), std::string::npos);
}
#endif
