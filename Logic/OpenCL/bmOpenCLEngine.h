// bmOpenCLEngine.h - the VPS frame of bmCpuEngine.h (Faieghi et al.) on an OpenCL device.
//
// Same frame, same results: the kernels (Kernels/bmVpsFrame.cl) repeat the CPU engine's
// arithmetic in the same order and precision, and the host culls blocks with the CPU engine's two
// rules (bmCpuEngine.h), so thrust, torque, removal and the cut voxmap are identical to
// bm::CpuEngine's (a test asserts it on PoCL). Per frame:
//  1. host: transform, culling of the Morton-sorted shell blocks against the coarse brick
//     occupancy (kept current from the voxels the device reports voided), the visible block list
//     written to the device;
//  2. vps_collide: per element collision, residency, removal request and elemental force, sums
//     per work-group (no per-element atomics);
//  3. vps_remove: requests of one voxel merged along the Morton order, one atomic subtraction per
//     run, voided voxels listed;
//  4. host: sums read back and added in int64 (exact in any order).
// Shell, voxmap fill, residency state and force table live on the device between frames; the
// program is built and both kernels run once in the constructor, so the first frame does not pay
// for compilation. The caller's Voxmap is brought up to date by SyncBone() (the device holds the
// cut state in between).
#pragma once

#include <memory>
#include <vector>

#include "bmEngine.h"
#include "bmForceModel.h"
#include "bmOpenCLRuntime.h"
#include "bmPointShell.h"
#include "bmVoxmap.h"

namespace bm {

class OpenCLEngine final : public Engine {
public:
  /// Uploads shell and voxmap, builds and warms up the kernels. bone, tool, shell and model must
  /// outlive the engine. Throws std::runtime_error when the device cannot be used.
  OpenCLEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
               const ForceModel& model, const OpenCLOptions& options = {});
  /// "opencl/<method>".
  std::string Name() const override { return "opencl/" + ToString(Model_.GetMethod()); }
  /// Throws std::runtime_error on a device fault (the device's cut state is then undefined).
  FrameResult Step(const FrameInput& in) override;
  /// Reads the device's fills back into the Voxmap given at construction.
  void SyncBone() override;
  const OpenCLRuntime& Runtime() const { return Rt_; }
  /// Bytes held on the device.
  size_t DeviceBytes() const { return Rt_.deviceBytes; }

private:
  void UpdateForceTable(double f, double n);
  bool AnyBoneIn(std::array<int, 3> lo, std::array<int, 3> hi) const;

  Voxmap& Bone_;
  const ToolModel& Tool_;
  const PointShell& Shell_;
  ForceModel Model_;
  OpenCLRuntime Rt_;
  cl::Program Program_;
  cl::Kernel Collide_, Remove_;
  cl::Buffer Codes_, Normals_, Bins_, Deltas_, Ranges_, Radial_, Table_, Fill_, Material_, State_,
      Units_, Visible_, Sums_, RemovalSums_, VoidedCount_, Voided_;
  std::vector<int32_t> Bricks_;        // host copy of the brick occupancy
  std::vector<uint32_t> Visible_Host_; // visible block indices of the frame
  std::vector<int64_t> SumsHost_, RemovalSumsHost_;
  std::vector<int64_t> VoidedHost_;
  std::vector<BinForce> TableHost_;
  uint32_t Frame_ = 0;
  bool Warming_ = false; // constructor's warm-up: launch the kernels even with no block visible
  double TableFeed_ = -1, TableSpeed_ = -1;
};

} // namespace bm
