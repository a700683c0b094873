// bmMachiningSetup.h - everything one run of a scene needs, built once: tool, point shell, force
// model, the bone voxmap and the engine cutting it. Shared by bmsim, the benchmark, the session
// and the plugin, so no face builds these its own way.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "bmEngine.h"
#include "bmForceModel.h"
#include "bmPointShell.h"
#include "bmScene.h"
#include "bmToolModel.h"
#include "bmVoxmap.h"

namespace bm {

class MachiningSetup {
public:
  /// Builds tool, shell, model and engine for `scene` around `bone` (the setup owns it).
  /// device: the backend's device choice ("" = default); deviceHeldBone: EngineContext's (default
  /// false: Bone() is current after every frame). Throws on bad input or backend failure.
  MachiningSetup(const Scene& scene, Voxmap bone, const std::string& device = "",
                 bool deviceHeldBone = false);
  MachiningSetup(const MachiningSetup&) = delete;
  MachiningSetup& operator=(const MachiningSetup&) = delete;

  const Scene& GetScene() const { return Scene_; }
  const ToolModel& Tool() const { return *Tool_; }
  const PointShell& Shell() const { return Shell_; }
  const ForceModel& Model() const { return Model_; }
  Voxmap& Bone() { return Bone_; }
  Engine& GetEngine() { return *Engine_; }
  /// Tool -> world rotation that carries z_t onto the trial axis.
  Eigen::Matrix3d ToolRotation() const;

private:
  Scene Scene_;
  std::unique_ptr<ToolModel> Tool_;
  PointShell Shell_;
  ForceModel Model_;
  Voxmap Bone_;
  std::unique_ptr<Engine> Engine_;
};

/// The voxmap of a block scene (bone.type == "block"); CT scenes are built by the IO library.
Voxmap MakeSceneBlock(const Scene& scene);

} // namespace bm
