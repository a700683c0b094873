#include "bmMachiningSetup.h"

#include <iostream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "bmBoneBlock.h"
#include "bmEngineFactory.h"

namespace bm {

MachiningSetup::MachiningSetup(const Scene& scene, Voxmap bone, const std::string& device,
                               bool deviceHeldBone)
    : Scene_(scene), Tool_(MakeTool(scene.tool)),
      Shell_(PointShell::Build(*Tool_, scene.shellResolution, scene.lips)),
      Model_(scene.forceModel.is_null() ? ForceModel::Default(scene.method, *Tool_)
                                        : ForceModel::FromJson(scene.forceModel, *Tool_)),
      Bone_(std::move(bone)) {
  if (Model_.GetMethod() != scene.method)
    throw std::invalid_argument("force_model.method disagrees with the scene's method");
  const EngineContext ctx{Bone_, *Tool_, Shell_, Model_, scene.threads, device, deviceHeldBone};
  try {
    Engine_ = MakeEngine(scene.backend, ctx);
  } catch (const std::runtime_error& e) {
    // A backend that fails to start (no OpenCL platform, unusable device) falls back to the
    // CPU backend, saying so; unknown backend names (std::invalid_argument) still throw.
    if (scene.backend == "cpu")
      throw;
    std::cerr << "backend '" << scene.backend << "' failed: " << e.what()
              << "; running on the CPU backend\n";
    Engine_ = MakeEngine("cpu", ctx);
  }
}

Eigen::Matrix3d MachiningSetup::ToolRotation() const {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(),
                                            Scene_.trial.axis.normalized())
      .toRotationMatrix();
}

Voxmap MakeSceneBlock(const Scene& scene) {
  if (scene.bone.type != "block")
    throw std::invalid_argument("scene bone is not a block");
  return MakeBoneBlock(scene.bone.sizeMm, scene.voxmapResolution, float(scene.bone.material));
}

} // namespace bm
