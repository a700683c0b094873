// bmOpenCLEngine.h - the VPS frame of bmCpuEngine.h (Faieghi et al.) on an OpenCL device.
//
// Same frame, same results: the kernels (Kernels/bmVpsFrame.cl) repeat the CPU engine's
// arithmetic in the same order and precision, culling included, so thrust, torque, removal and
// the cut voxmap are identical to bm::CpuEngine's (tests assert it on PoCL, and on whatever
// device runs them). Per frame:
//  1. host: the frame's geometry (bmFrameGeometry.h) as kernel arguments; no launch at all when
//     the tool's box meets no bone (the host's brick occupancy, or the voxmap's bounds when the
//     bone is held on the device);
//  2. vps_collide: per block, culling against the device's brick occupancy; per element of a
//     visible block collision, residency, removal request and elemental force; sums per
//     work-group (no per-element atomics);
//  3. vps_remove: requests of one voxel merged along the Morton order, one atomic subtraction per
//     run, bricks' counts kept;
//  4. host: the frame's sums read back (one read) and added in int64 (exact in any order).
// Shell, voxmap fill, brick occupancy, residency state and force table live on the device between
// frames; the program is built and both kernels run once in the constructor, so the first frame
// does not pay for compilation.
//
// The caller's Voxmap (OpenCLOptions::deviceHeldBone):
//  - false (default): kept current after every frame, as the CPU engine keeps it, so that a
//    haptic session's contact and live view read the cut bone. The removal kernel logs its merged
//    requests (voxel, units) and the host applies them (Voxmap::RemoveOwned, the CPU engine's
//    removal): the same fills, bricks and change generations; the host's removal totals must
//    equal the device's, or the frame throws.
//  - true: the device alone holds the cut; SyncBone() reads it back. Only the frame's sums cross
//    the bus: the engine as the paper measures it (benchmarks).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "bmEngine.h"
#include "bmFrameGeometry.h"
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
  ~OpenCLEngine() override;
  OpenCLEngine(const OpenCLEngine&) = delete;
  OpenCLEngine& operator=(const OpenCLEngine&) = delete;
  /// "opencl/<method>".
  /// "opencl/<method>", with "/device-bone" when the bone is held on the device.
  std::string Name() const override {
    return "opencl/" + ToString(Model_.GetMethod()) + (Rt_.deviceHeldBone ? "/device-bone" : "");
  }
  /// Throws std::runtime_error on a device fault (the device's cut state is then undefined).
  FrameResult Step(const FrameInput& in) override;
  /// With deviceHeldBone: reads the device's fills back into the Voxmap given at construction
  /// (without it the Voxmap is already current: nothing to do).
  void SyncBone() override;
  /// The device's fills (StorageSize() entries, Voxmap::FillData's layout): what a test compares
  /// with the host's Voxmap.
  std::vector<int32_t> DeviceFills() const;
  const OpenCLRuntime& Runtime() const { return Rt_; }
  /// Bytes held on the device.
  size_t DeviceBytes() const { return Rt_.deviceBytes; }

private:
  void UpdateForceTable(double f, double n);
  /// Sets the kernels' arguments that stay the same from frame to frame (buffers, sizes).
  void SetFixedArgs();
  /// Whether any block could be visible this frame (no launch otherwise): the union of the
  /// shell's blocks' boxes, grown by one shell spacing, meets bone.
  bool MayMeetBone(const FrameGeometry& geo) const;
  /// Applies the removal log of the frame (logLength entries) to the host's Voxmap.
  Voxmap::RemovalTotals ApplyLog(size_t logLength);

  Voxmap& Bone_;
  const ToolModel& Tool_;
  const PointShell& Shell_;
  ForceModel Model_;
  OpenCLRuntime Rt_;
  cl::Program Program_;
  cl::Kernel Collide_, Remove_;
  cl::Buffer Codes_, Normals_, Bins_, Deltas_, BlockBox_, BlockInfo_, Radial_, Table_, Fill_,
      Material_, Bricks_, VisibleFrame_, State_, Units_, Partials_, RemovalPartials_, Meta_, Log_,
      MetaPinned_;
  int64_t* MetaPinnedHost_ = nullptr; // MetaPinned_ mapped: where each frame's sums are read
  std::array<float, 3> ShellLo_{}, ShellHi_{}; // union of the blocks' boxes, tool frame, mm
  std::vector<int64_t> PartialsHost_, RemovalPartialsHost_;
  std::vector<int64_t> LogHost_;
  std::vector<Voxmap::RemovalRequest> Requests_;
  std::vector<int64_t> Touched_;
  std::vector<BinForce> TableHost_;
  uint32_t Frame_ = 0;
  uint32_t Half_ = 0;    // the meta buffer's half the next launched frame uses
  bool Warming_ = false; // constructor's warm-up: launch the kernels whatever the geometry
  double TableFeed_ = -1, TableSpeed_ = -1;
};

} // namespace bm
