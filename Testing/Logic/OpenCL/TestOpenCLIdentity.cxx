// The OpenCL backend gives exactly the CPU backend's results: same fixed-point totals,
// same removal, same cut voxmap, frame by frame, for both methods, on whatever OpenCL device the
// machine has (PoCL in CI; BM_TEST_OPENCL_DEVICE names another, e.g. a GPU). The CPU engines are
// the kernels' plain C++ twins. The VPS engine keeps the caller's voxmap current after every frame
// (compared every frame, and with the device's own fills at the end) unless the bone is held on
// the device (then compared after SyncBone).
#include <algorithm>
#include <cstdlib>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "bmBoneBlock.h"
#include "bmCpuEngine.h"
#include "bmOpenCLDevice.h"
#include "bmOpenCLEngine.h"
#include "bmOpenCLZhengEngine.h"
#include "bmToolModel.h"
#include "bmZhengEngine.h"

namespace {

struct Case {
  int voxmap = 64;
  int shell = 256;
  float material = 1.0f;
  bm::LipMode lips = bm::LipMode::TimeAveraged;
  Eigen::Vector3d axis{0, 0, 1};  // tool axis (world), out of the bone
  Eigen::Vector3d drift{0, 0, 0}; // lateral motion per frame, mm
  bool envelope = true;           // FrameInput::envelopeRemoves
  bool excursion = false;         // frames 60-63 far above the block (nothing launched)
  bm::OpenCLOptions options;
};

bool HaveDevice() {
  return !bm::ListOpenCLDevices().empty();
}

// The device the tests run on: $BM_TEST_OPENCL_DEVICE (a number or part of a name, as
// bmsim --cl-device), else the backend's default.
std::string TestDevice() {
  const char* d = std::getenv("BM_TEST_OPENCL_DEVICE");
  return d ? d : "";
}

// Feeds the drill along -axis in 0.01 mm steps from above the block to 0.8 mm deep (partial then
// full engagement of the lips), then retracts it a little (elements entering cut voxels), with
// both engines on copies of one block; compares every frame and the voxmaps at the end. Returns
// the fill units removed (CPU engine).
template <class CpuT, class OclT> int64_t ExpectIdentical(const Case& c, bm::Method method) {
  const auto tool = bm::MakeTool(nlohmann::json{{"type", "drill"}});
  const bm::PointShell shell = bm::PointShell::Build(*tool, c.shell, c.lips);
  const bm::ForceModel model = bm::ForceModel::Default(method, *tool);
  bm::Voxmap boneCpu = bm::MakeBoneBlock({5, 5, 1.5}, c.voxmap, c.material);
  bm::Voxmap boneOcl = boneCpu;
  CpuT cpu(boneCpu, *tool, shell, model, 2);
  bm::OpenCLOptions options = c.options;
  options.device = TestDevice();
  OclT ocl(boneOcl, *tool, shell, model, options);
  // The VPS engine's voxmap is current after every frame unless the device holds the bone.
  constexpr bool kVps = std::is_same_v<OclT, bm::OpenCLEngine>;
  const bool mirrored = kVps && !options.deviceHeldBone;
  const Eigen::Matrix3d rot =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), c.axis.normalized())
          .toRotationMatrix();
  const Eigen::Vector3d axis = c.axis.normalized();
  Eigen::Vector3d pos = 0.05 * axis;
  int engagedFrames = 0;
  int64_t removed = 0;
  for (int frame = 0; frame < 100; ++frame) {
    bm::FrameInput in;
    in.envelopeRemoves = c.envelope;
    in.rotation = rot;
    in.motion = (frame < 85 ? -0.01 : 0.004) * axis + c.drift;
    pos += in.motion;
    in.position = c.excursion && frame >= 60 && frame < 64 ? Eigen::Vector3d(pos + 40 * axis) : pos;
    in.spindleAngle = 0.3 * frame;
    const bm::FrameResult a = cpu.Step(in);
    const bm::FrameResult b = ocl.Step(in);
    SCOPED_TRACE("frame " + std::to_string(frame));
    EXPECT_EQ(a.thrustFixed, b.thrustFixed);
    EXPECT_EQ(a.torqueFixed, b.torqueFixed);
    EXPECT_EQ(a.thrustN, b.thrustN);
    EXPECT_EQ(a.torqueNmm, b.torqueNmm);
    EXPECT_EQ(a.forceTool, b.forceTool);
    EXPECT_EQ(a.visitedElements, b.visitedElements);
    EXPECT_EQ(a.engagedElements, b.engagedElements);
    EXPECT_EQ(a.engagedCutting, b.engagedCutting);
    EXPECT_EQ(a.removedFill, b.removedFill);
    EXPECT_EQ(a.removedVoxels, b.removedVoxels);
    EXPECT_EQ(a.sweptVolumeMm3, b.sweptVolumeMm3);
    if (mirrored) {
      EXPECT_TRUE(boneCpu == boneOcl);
    }
    if (a.engagedCutting > 0)
      ++engagedFrames;
    removed += a.removedFill;
    if (::testing::Test::HasFailure())
      return removed;
  }
  EXPECT_GT(engagedFrames, 40); // the comparison covered real cutting
  if constexpr (kVps)
    if (mirrored) { // the host's copy is the device's bone
      const std::vector<int32_t> device = ocl.DeviceFills();
      EXPECT_TRUE(std::equal(device.begin(), device.end(), boneOcl.FillData()));
    }
  cpu.SyncBone();
  ocl.SyncBone();
  EXPECT_LT(boneOcl.CountBone(), bm::MakeBoneBlock({5, 5, 1.5}, c.voxmap, c.material).CountBone());
  EXPECT_TRUE(boneCpu == boneOcl);
  return removed;
}

TEST(OpenCLIdentity, LazarMatchesCpuEngine) {
  if (!HaveDevice())
    GTEST_SKIP() << "no OpenCL device";
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(Case{}, bm::Method::Lazar);
}

// The bone held on the device alone (the benchmark's way): the same frames, and the same cut bone
// once read back.
TEST(OpenCLIdentity, LazarWithTheBoneHeldOnTheDevice) {
  if (!HaveDevice())
    GTEST_SKIP() << "no OpenCL device";
  Case c;
  c.options.deviceHeldBone = true;
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
  c.axis = {0.2, -0.1, 1};
  c.drift = {0.002, 0.001, 0};
  c.material = 0.7f;
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
}

TEST(OpenCLIdentity, LazarInclinedWithMaterialAndInstantaneousLips) {
  if (!HaveDevice())
    GTEST_SKIP() << "no OpenCL device";
  Case c;
  c.material = 0.6f;
  c.lips = bm::LipMode::Instantaneous;
  c.axis = {0.2, -0.1, 1};
  c.drift = {0.002, 0.001, 0};
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
}

// Frames in which the tool is far from the block launch nothing on the device; the CPU engine
// culls every block in them. Back in the bone the elements' residency goes on alike.
TEST(OpenCLIdentity, LazarFramesAwayFromTheBone) {
  if (!HaveDevice())
    GTEST_SKIP() << "no OpenCL device";
  Case c;
  c.excursion = true;
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
  c.options.deviceHeldBone = true;
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
}

// The GPU way of splitting work (work-groups of several lanes with local sums, 64-bit atomics),
// exercised on whatever device runs the test.
TEST(OpenCLIdentity, LazarGroupSumsAndInt64Atomics) {
  const auto devices = bm::ListOpenCLDevices();
  if (devices.empty())
    GTEST_SKIP() << "no OpenCL device";
  Case c;
  c.voxmap = 96;
  c.options.lanes = 8;
  c.options.groups = 64;
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
  bm::OpenCLDeviceInfo info;
  bm::ChooseOpenCLDevice(TestDevice(), &info);
  if (!info.int64Atomics)
    GTEST_SKIP() << "device lacks cl_khr_int64_base_atomics";
  c.options.int64Atomics = 1;
  ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
}

TEST(OpenCLIdentity, ZhengMatchesCpuBaseline) {
  if (!HaveDevice())
    GTEST_SKIP() << "no OpenCL device";
  ExpectIdentical<bm::ZhengEngine, bm::OpenCLZhengEngine>(Case{}, bm::Method::Zheng);
  Case c;
  c.material = 0.8f;
  c.axis = {-0.1, 0.15, 1};
  c.options.lanes = 4;
  c.options.groups = 16;
  ExpectIdentical<bm::ZhengEngine, bm::OpenCLZhengEngine>(c, bm::Method::Zheng);
  c.lips = bm::LipMode::Instantaneous;
  c.drift = {-0.001, 0.002, 0};
  ExpectIdentical<bm::ZhengEngine, bm::OpenCLZhengEngine>(c, bm::Method::Zheng);
}

TEST(OpenCLDevices, ChoosingADevice) {
  const auto devices = bm::ListOpenCLDevices();
  if (devices.empty()) {
    EXPECT_THROW(bm::ChooseOpenCLDevice(""), std::runtime_error);
    return;
  }
  bm::OpenCLDeviceInfo info;
  bm::ChooseOpenCLDevice("0", &info);
  EXPECT_EQ(info.index, 0);
  EXPECT_EQ(info.name, devices[0].name);
  EXPECT_THROW(bm::ChooseOpenCLDevice(std::to_string(devices.size())), std::runtime_error);
  EXPECT_THROW(bm::ChooseOpenCLDevice("no such device name"), std::runtime_error);
}

// Only cutting elements remove (the haptic session's rule, FrameInput::envelopeRemoves off): the
// same on both backends, for both methods, and it removes less than the envelope when the tool
// drifts sideways (the margins then face the motion).
TEST(OpenCLIdentity, OnlyCuttingElementsRemoveWithoutTheEnvelope) {
  if (!HaveDevice())
    GTEST_SKIP() << "no OpenCL device";
  Case c;
  c.axis = {0.2, -0.1, 1};
  c.drift = {0.002, 0.001, 0};
  const int64_t envelope = ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
  c.envelope = false;
  const int64_t lips = ExpectIdentical<bm::CpuEngine, bm::OpenCLEngine>(c, bm::Method::Lazar);
  EXPECT_LT(lips, envelope);
  EXPECT_GT(lips, 0);
  ExpectIdentical<bm::ZhengEngine, bm::OpenCLZhengEngine>(c, bm::Method::Zheng);
}

} // namespace
