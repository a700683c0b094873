// bmSceneOverrides.h - a scene named by the user (built-in name or scene file) with the changes a
// command line or a panel asks for (resolutions, tool, force model, bone, trial), applied by one
// rule everywhere: bmsim run, bmsim bench, the BM Session source (Docs/Session.md, "Building a
// session").
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "bmScene.h"

namespace bm {

/// Changes to a scene. Every field is optional: unset (empty, 0 or nullopt) keeps the scene's.
struct SceneOverrides {
  /// Voxmap cells along the bone's longest side, in [8, 4096] (0: the scene's). Set alone, the
  /// point shell scales alike (Scene::WithVoxmapResolution: the grids keep the scene's ratio).
  int voxmapResolution = 0;
  /// Point-shell cells along the tool's longest side, in [8, 4096] (0: the scene's).
  int shellResolution = 0;
  /// The tool as a JSON object {"type": "drill" | "reamer" | "burr", parameters...} (bm::MakeTool's
  /// keys, units in the key names), replacing the scene's ("": the scene's).
  std::string toolJson;
  /// Force model and pipeline: "lazar" or "zheng" ("": the scene's); another method than the
  /// scene's drops the scene's force-model coefficients (that method's defaults apply).
  std::string method;
  /// A voxmap file (.nrrd or .mha, as saved from a session) machined instead of the scene's bone,
  /// at its own resolution ("": the scene's bone).
  std::string boneFile;
  /// A CT bone as JSON: the "ct" description of a scene's bone ({"ct": folder-or-file,
  /// "threshold": HU, "roi": [x0, y0, z0, x1, y1, z1] mm, ...}), imported at the voxmap
  /// resolution ("": the scene's bone). Exclusive with boneFile.
  std::string boneCTJson;
  /// Trial entry point, world mm, and axis (world, from the bone out toward the shank; any
  /// non-zero length, normalised). Both or neither.
  std::optional<Eigen::Vector3d> entryMm, axis;
  /// Trial feed per revolution, mm/rev, in [1e-5, 1], and spindle speed, rpm, in [1, 1e5].
  std::optional<double> feedMmPerRev, speedRpm;
  /// CPU threads, in [1, 64].
  std::optional<int> threads;
  /// Compute backend "cpu" | "opencl" and lip model "averaged" | "instantaneous" ("": the scene's).
  std::string backend, lips;
};

/// A built-in scene by name (Scene::Builtin) or a scene file: a name ending in .json or naming an
/// existing file is read as a file (Scene::Load). Throws std::invalid_argument (unknown name) or
/// std::runtime_error (unreadable file).
Scene ResolveScene(const std::string& nameOrFile);

/// The scene with the overrides applied; the scene's baseDir is kept (relative CT and voxmap paths
/// of the scene still resolve), a bone file is made absolute. Throws std::invalid_argument naming
/// the override and its range when a value is out of range, not JSON, or both bone overrides are
/// set, and std::runtime_error when the bone file does not exist.
Scene ApplyOverrides(const Scene& scene, const SceneOverrides& o);

} // namespace bm
