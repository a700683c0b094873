// bmZhengEngine.h - the baseline: Zheng et al.'s pipeline in the same harness (Docs/Model.md
// section 4).
//
// Differences from bmCpuEngine, all faithful to the baseline:
//  - the voxmap is held in an octree (bmOctreeVoxmap.h) walked from the root for every query;
//  - only the tool's global bounding box is checked before the per-element pass (no block culling);
//  - every element's force is evaluated from the model's formulas (k = a + b/V, mu = 0 on the
//    lips) and written to a per-element buffer; a separate reduction pass sums the buffer (in a
//    fixed chunking, so the totals do not depend on the thread count).
// Removal conserves material exactly as the VPS engine does (same harness, same removal rule).
#pragma once

#include <memory>
#include <vector>

#include "bmElementResidency.h"
#include "bmEngine.h"
#include "bmForceModel.h"
#include "bmOctreeVoxmap.h"
#include "bmPointShell.h"
#include "bmVoxmap.h"
#include "bmWorkerPool.h"

namespace bm {

class ZhengEngine final : public Engine {
public:
  /// Builds the octree from `bone`; SyncBone() writes the cut state back into it.
  ZhengEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell, const ForceModel& model,
              int threads = 2);
  std::string Name() const override { return "cpu/zheng-octree"; }
  FrameResult Step(const FrameInput& in) override;
  void SyncBone() override;
  const OctreeVoxmap& Octree() const { return Tree_; }

private:
  Voxmap& Bone_;
  const ToolModel& Tool_;
  const PointShell& Shell_;
  ForceModel Model_;
  OctreeVoxmap Tree_;
  WorkerPool Pool_;
  std::vector<std::array<double, 4>> Buffer_; // per element: (fx, fy, thrust, torque)
  struct Request {
    uint32_t element;
    int32_t units;
    std::array<int, 3> ijk;
  };
  std::vector<std::vector<Request>> Requests_; // per thread
  std::vector<int64_t> Engaged_, EngagedCut_, Visited_;
  std::vector<ElementResidency> State_; // per element, as bmCpuEngine
  uint32_t Frame_ = 0;
};

} // namespace bm
