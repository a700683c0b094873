// bmSessionGrid.h - the resolutions and engine threads a haptic session models: no more than the
// scene needs (Docs/RealTime.md, "Choosing a session's resolutions").
//
// A session's voxmap is
//  - no finer than the scene's own voxmap (what the offline trial's accuracy asks for);
//  - no finer than this machine's measured limit for the scene: the finest voxmap of the session
//    table (bmSessionBenchTable.h, `bmsim bench --session`) whose frame p99 on the incremental
//    path is within the haptic period, with or without the live view as the session will run;
//  - for a CT bone, no finer than the CT's finest spacing (the import's "noFinerThanCT", applied
//    where the CT is read: bmImport.h, bmVoxmapResampler.h CellsNoFinerThan), unless the tool
//    needs finer voxels (ToolVoxelMm: kVoxelsAcrossTool across its diameter);
// and the point shell keeps the scene's grid ratio (Scene::WithVoxmapResolution). The engine's
// threads are those with the lowest measured p99 at that voxmap.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bmScene.h"
#include "bmSessionAccuracyTable.h"
#include "bmSessionBenchTable.h"

namespace bm {

/// This machine's measured limit for a scene's sessions.
struct SessionLimit {
  int voxmap = 0;     ///< the finest measured voxmap that holds the period (or the coarsest)
  int threads = 0;    ///< engine threads with the lowest p99 there
  double p99Ms = 0;   ///< its worst measured frame p99, ms
  bool holds = false; ///< p99 within the period (false: no measured voxmap holds it)
  std::string machine, date;
};

/// The limit from `rows` for scene `sceneName` on the incremental path, with the live view
/// (`view`) or without, for a haptic period of periodMs (ms, > 0). A (voxmap, threads) cell is
/// judged by its worst p99 over its runs. None when the table has no such rows.
std::optional<SessionLimit> MeasuredSessionLimit(const std::vector<SessionBenchRow>& rows,
                                                 const std::string& sceneName, bool view,
                                                 double periodMs);

/// The session table at DefaultSessionBenchPath(), or none (empty) when it is missing or
/// unreadable; `error` (optional) receives why.
std::vector<SessionBenchRow> LoadDefaultSessionTable(std::string* error = nullptr);

/// What a session will model before its bone is read: the scene with its voxmap capped by the
/// measured limit (the shell scaled alike) and the limit's threads, and the reasons in words.
struct SessionGridPlan {
  Scene scene;
  std::optional<SessionLimit> limit;
  std::string reason;
};
/// Plans the grid of a session on `scene` at rateHz (Hz, > 0) with or without the live view. The
/// reason ends with what the chosen voxmap buys in accuracy when `accuracy` (the session accuracy
/// table, bmSessionAccuracyTable.h) has its row.
SessionGridPlan PlanSessionGrid(const Scene& scene, const std::vector<SessionBenchRow>& table,
                                bool view, double rateHz,
                                const std::vector<SessionAccuracyRow>& accuracy = {});

/// Voxels a session keeps across the tool's diameter even on a coarse CT: the engine samples
/// removal and force per voxel, so a tool a few voxels wide cuts a jagged hole with aliased forces.
constexpr int kVoxelsAcrossTool = 8;
/// The coarsest voxel (mm) that resolves a tool of outer radius toolRadiusMm (mm):
/// 2 x radius / kVoxelsAcrossTool (a 2 mm burr: 0.5 mm; the 36.5 mm reamer: 4.6 mm).
double ToolVoxelMm(double toolRadiusMm);

} // namespace bm
