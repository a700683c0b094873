// bmScene.h - what a machining run simulates: bone, tool, trial, method, resolutions.
//
// Scenes are JSON (nlohmann-json). Built-in scenes: "drilling" (the reference drill fed into a
// cortical block like a robot-driven trial). Every field is optional; defaults are the built-in
// drilling scene's. A bad field gives std::invalid_argument naming it.
//
// {
//   "name": "drilling",
//   "tool": {"type": "drill", ...bmToolModel.h parameters},
//   "bone": {"type": "block", "size_mm": [5, 5, 1.5], "material": 1.0}
//         | {"type": "ct", "path": "...", ... import settings read by the CT importer},
//   "trial": {"feed_mm_per_rev": 0.02, "speed_rpm": 1000, "entry_mm": [0, 0, 0],
//             "axis": [0, 0, 1], "clearance_mm": 0.02, "depth_mm": null, "extra_depth_mm": 0.3,
//             "frame_s": 0.001},
//   "voxmap_resolution": 256, "shell_resolution": 1024,
//   "method": "lazar" | "zheng", "lips": "averaged" | "instantaneous", "threads": 2,
//   "backend": "cpu" | "opencl", "force_model": {...bmForceModel.h ToJson()}
// }
// Trial: the tool axis z_t points along "axis" (world, from the bone out toward the shank); the
// tool is fed along -axis at v = f n / 60 mm/s from `clearance_mm` above the entry point until its
// foremost cutting point is `depth_mm` below it (default: full engagement of the edges plus
// `extra_depth_mm`).
//
// Default resolutions: with the reference drill (10 mm modelled) at shell 1024 (9.8 um) and the
// 5 mm block at voxmap 256 (19.5 um) the two grids align 2:1 on the axis, which keeps the
// removal's aliasing small (removed volume within ~5 % of the swept volume) while the forces
// match the quadrature within 0.5 %.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "bmForceModel.h"
#include "bmPointShell.h"
#include "bmToolModel.h"

namespace bm {

struct TrialSpec {
  double feedMmPerRev = 0.02;     ///< f, mm/rev
  double speedRpm = 1000;         ///< n, rpm
  Eigen::Vector3d entry{0, 0, 0}; ///< world mm: where the axis enters the bone surface
  Eigen::Vector3d axis{0, 0, 1};  ///< world unit vector of z_t (out of the bone)
  double clearanceMm = 0.02;      ///< start this far above the entry point, mm
  double depthMm = -1;       ///< final depth of the foremost cutting point, mm (< 0: automatic)
  double extraDepthMm = 0.3; ///< automatic depth = full edge engagement + this, mm
  double frameS = 0.001;     ///< frame period, s (1 kHz)
};

struct BoneSpec {
  std::string type = "block"; ///< "block" or "ct"
  std::array<double, 3> sizeMm{5.0, 5.0,
                               1.5}; ///< block: x, y, z extent; top face at z = 0, centred
  double material = 1.0;             ///< block: material scale (1 = cortical)
  nlohmann::json ct;                 ///< ct: the importer's settings (path, threshold, roi...)
};

/// One step of a plan (e.g. the guide-pin hole, then the reaming): its own tool and trial on the
/// bone the previous steps left. JSON: {"name": "guide pin", "description": "...",
/// "tool": {...}, "trial": {...fields over the scene's trial}, "shell_resolution": N}; a field left
/// out is the scene's.
struct SceneStep {
  std::string name;        ///< short name, also the step's output folder ("1-guide-pin")
  std::string description; ///< one sentence for the report
  nlohmann::json tool;     ///< the step's tool (bmToolModel.h parameters)
  nlohmann::json trial;    ///< trial fields that differ from the scene's
  int shellResolution = 0; ///< cells along this tool's longest side; 0 = the scene's
};

struct Scene {
  std::string name = "drilling";
  nlohmann::json tool = {{"type", "drill"}};
  BoneSpec bone;
  TrialSpec trial;
  int voxmapResolution = 256; ///< cells along the bone's (cropped) bounding box's longest side
  int shellResolution = 1024; ///< cells along the tool's bounding box's longest side
  Method method = Method::Lazar;
  LipMode lips = LipMode::TimeAveraged;
  int threads = 2;
  std::string backend = "cpu";
  nlohmann::json forceModel; ///< empty: the method's defaults
  /// A plan: steps run in order on one bone, each with its own tool and trial (empty: the scene is
  /// one run of `tool` and `trial`). See SceneStep.
  std::vector<SceneStep> steps;
  nlohmann::json planning; ///< a plan's measurements and choices, carried to its report

  /// The scene of step i (0-based): this scene with the step's tool, trial and shell resolution,
  /// no steps, named "<scene>: <step>". Throws std::out_of_range for a step that does not exist
  /// and std::invalid_argument naming the step for a bad field.
  Scene Step(size_t i) const;

  /// Parse and validate; throws std::invalid_argument naming the bad field.
  static Scene FromJson(const nlohmann::json& j);
  /// This scene at another voxmap resolution (cells, in [8, 4096]) with the point shell scaled
  /// alike (rounded, clamped to [8, 4096]), so the two grids keep the scene's ratio: the built-in
  /// scenes put them 2:1 (shell spacing half the voxel). A shell coarser than that leaves voxels
  /// that no element visits standing in the cut and removes less than the tool sweeps (glenoid at
  /// voxmap 512 with its shell of 340: half the volume). Throws std::invalid_argument on a
  /// resolution out of range.
  Scene WithVoxmapResolution(int cells) const;
  /// Folder that relative paths in the scene (CT, voxmap) are taken from; "" = current folder.
  std::string baseDir;

  /// A built-in scene by name: "drilling" (in code) or Resources/Scenes/<name>.json; throws
  /// std::invalid_argument listing the names.
  static Scene Builtin(const std::string& name);
  /// Names of the built-in scenes, "drilling" first.
  static std::vector<std::string> BuiltinNames();
  /// Read a scene file; throws std::runtime_error if unreadable or not JSON.
  static Scene Load(const std::string& path);
  nlohmann::json ToJson() const;
  /// Checks ranges (resolutions 8..4096, threads 1..64, feed and speed > 0, ...).
  void Validate() const;
};

} // namespace bm
