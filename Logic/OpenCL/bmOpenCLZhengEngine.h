// bmOpenCLZhengEngine.h - the Zheng et al. baseline of bmZhengEngine.h on an OpenCL device.
//
// Same pipeline and results as bm::ZhengEngine (a test asserts identity on PoCL): global
// bounding-box pre-check on the host; zheng_collide walks the octree from the root for every
// element (no block culling) and writes elemental forces to a per-element buffer; zheng_reduce
// sums the buffer in the CPU baseline's fixed chunks (the host adds the chunk sums in order, in
// double, as the CPU baseline does); zheng_remove cuts the voxel-level leaves.
// What differs from a pure-device pipeline, stated plainly: the octree's refinement (splitting a
// coarse leaf down to the voxel a removal request falls in) runs on the host between the collision
// and the removal kernels, on a host copy of the tree's structure, and only the new and split
// nodes are uploaded. Leaves coarser than a voxel are never cut, so the host copy's values of the
// leaves it splits are always current.
#pragma once

#include <vector>

#include "bmEngine.h"
#include "bmForceModel.h"
#include "bmOpenCLRuntime.h"
#include "bmPointShell.h"
#include "bmVoxmap.h"

namespace bm {

class OpenCLZhengEngine final : public Engine {
public:
  /// Builds the octree of `bone`, uploads it and the shell, builds and warms up the kernels.
  /// Throws std::runtime_error when the device cannot be used.
  OpenCLZhengEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
                    const ForceModel& model, const OpenCLOptions& options = {});
  std::string Name() const override { return "opencl/zheng-octree"; }
  /// Throws std::runtime_error on a device fault.
  FrameResult Step(const FrameInput& in) override;
  /// Writes every voxel's fill from the device's octree into the Voxmap given at construction.
  void SyncBone() override;
  const OpenCLRuntime& Runtime() const { return Rt_; }
  size_t DeviceBytes() const { return Rt_.deviceBytes; }
  size_t NodeCount() const { return Nodes_.size(); }

private:
  int32_t Build(int level, int i0, int j0, int k0);
  void Refine(int i, int j, int k);
  void UploadTree();
  void UpdateTerms(double f, double n);
  FrameResult Launch(const FrameInput& in, uint32_t frameNo);

  Voxmap& Bone_;
  const ToolModel& Tool_;
  const PointShell& Shell_;
  ForceModel Model_;
  OpenCLRuntime Rt_;
  cl::Program Program_;
  cl::Kernel Collide_, Reduce_, Remove_;
  cl::Buffer Codes_, Normals_, Bins_, Deltas_, Radial_, Terms_, Material_, State_, Units_, Buffer_,
      Sums_, RemovalSums_, ChunkSums_, RefineCount_, Refine_, NodesDev_;
  std::vector<cl_int2> Nodes_; // host copy of the tree (values of voxel leaves go stale)
  std::vector<int32_t> Dirty_; // split nodes not yet uploaded
  size_t Uploaded_ = 0;        // nodes [0, Uploaded_) are on the device
  size_t Capacity_ = 0;        // device node capacity
  int Levels_ = 0;
  std::vector<int64_t> SumsHost_, RemovalSumsHost_;
  std::vector<cl_double4> ChunkHost_;
  std::vector<cl_int4> RefineHost_;
  std::vector<double> TermsHost_;
  uint32_t Frame_ = 0;
  double TermsFeed_ = -1, TermsSpeed_ = -1;
};

} // namespace bm
