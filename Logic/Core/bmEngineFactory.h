// bmEngineFactory.h - choosing a backend by name ("cpu", "opencl", ...).
//
// The CPU backend is always there. Other backends register themselves with RegisterBackend()
// (the OpenCL library's bm::RegisterOpenCLBackend(), called by bmsim and the plugin at start).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bmEngine.h"
#include "bmForceModel.h"
#include "bmPointShell.h"
#include "bmToolModel.h"
#include "bmVoxmap.h"

namespace bm {

struct EngineContext {
  Voxmap& bone;
  const ToolModel& tool;
  const PointShell& shell;
  const ForceModel& model; ///< its method picks the Lazar (VPS) or Zheng (octree) pipeline
  int threads = 2;         ///< CPU threads
  std::string device;      ///< backend-specific device choice ("" = default)
  /// A backend with its own copy of the bone (OpenCL) may keep the cut there alone, the Voxmap
  /// brought up to date by Engine::SyncBone() (benchmarks). Default false: the Voxmap is current
  /// after every frame, as a haptic session's contact and live view need.
  bool deviceHeldBone = false;
};

using EngineMaker = std::function<std::unique_ptr<Engine>(const EngineContext&)>;

/// Registers (or replaces) a backend.
void RegisterBackend(const std::string& name, EngineMaker maker);
/// Names of the available backends, "cpu" first.
std::vector<std::string> Backends();
/// Creates an engine; throws std::invalid_argument for an unknown backend and std::runtime_error
/// when the backend fails to start (e.g. no OpenCL platform).
std::unique_ptr<Engine> MakeEngine(const std::string& backend, const EngineContext& ctx);

} // namespace bm
