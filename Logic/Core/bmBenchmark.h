// bmBenchmark.h - the speed-against-accuracy benchmark of `bmsim bench` (Docs/Performance.md).
//
// One cell = (method, backend, point-shell resolution, voxmap resolution) on the drilling scene
// with the lips fully engaged. The block is pre-cut analytically to the tool's swept envelope at
// the start depth (every voxel whose centre lies inside the solid of revolution of the tool fed
// from above: rho <= OuterRadius and z above the tool's lower surface ZRange(rho)), so full
// engagement is reached without feeding thousands of frames. Then `warmup` frames are fed and
// not timed, then `frames` frames are fed and each engine Step() is timed with steady_clock.
// Accuracy: mean thrust and torque over the timed frames against the same force model integrated
// along the edges (bmForceModel.h IntegrateEdges, full engagement): each method against its own
// quadrature, so the error is the discretisation error of the point shell and voxmap.
//
// Each cell runs in a forked child process (the parent must not have started threads or OpenCL):
// a crash, an OpenCL failure or the time limit ends the cell, not the sweep, and the child's peak
// resident memory (wait4 ru_maxrss: voxmap, shell, engine and device copies on PoCL, plus the
// process's baseline) is the cell's memory figure.
#pragma once

#include <string>
#include <vector>

#include "bmForceModel.h"
#include "bmScene.h"

namespace bm {

struct BenchOptions {
  std::vector<Method> methods{Method::Lazar, Method::Zheng};
  std::vector<std::string> backends{"cpu", "opencl"};
  std::vector<int> shells{128, 256, 512, 1024, 2048}; ///< point-shell resolutions
  std::vector<int> voxmaps{128, 256, 512, 1024};      ///< voxmap resolutions
  int frames = 1000;                                  ///< timed frames per cell (>= 1)
  int warmup = 100;                                   ///< untimed frames before them
  int threads = 2;                                    ///< CPU backend threads
  std::string device;                                 ///< OpenCL device choice ("" = default)
  /// OpenCL cells hold the cut bone on the device alone (default true: the engine as the paper
  /// measures it); false: the host's voxmap is kept current every frame, as in a session.
  bool deviceHeldBone = true;
  double cellLimitS = 600; ///< a cell still running after this many seconds is stopped
};

struct BenchCell {
  Method method = Method::Lazar;
  std::string backend;
  int shell = 0, voxmap = 0;
  std::string status = "ok"; ///< "ok", or why the cell has no figures
  std::string engine;        ///< Engine::Name()
  int64_t elements = 0;      ///< point-shell elements
  int frames = 0;            ///< timed frames
  double medianMs = 0, p99Ms = 0, meanMs = 0, sdMs = 0, maxMs = 0; ///< frame time, ms
  double thrustN = 0, torqueNmm = 0;                               ///< means over the timed frames
  double refThrustN = 0, refTorqueNmm = 0;                         ///< edge quadrature
  double thrustError = 0, torqueError = 0;                         ///< |mean - ref| / |ref|
  double forceError = 0;     ///< max(thrustError, torqueError)
  double engagedCutting = 0; ///< mean engaged cutting elements per frame
  double peakMemoryMb = 0;   ///< child's peak resident set, MiB
  double setupS = 0;         ///< building scene, shell, voxmap and engine, s
  std::string coefficients;  ///< the force model's coefficient set (ForceModel::Provenance)
  bool calibrated = false;   ///< whether that set was fitted to measured forces
};

/// The drilling scene of a cell (bm::Scene defaults: 10 mm reference drill, 5 x 5 x 1.5 mm
/// cortical block) at the given method, backend and resolutions.
Scene BenchScene(Method method, const std::string& backend, int shell, int voxmap, int threads);

/// Runs one cell in this process. Throws on failure.
BenchCell RunBenchCell(Method method, const std::string& backend, int shell, int voxmap,
                       const BenchOptions& options);

/// Runs one cell in a forked child and fills peakMemoryMb; never throws for a failing cell
/// (status says why). Call only while this process runs a single thread.
BenchCell RunBenchCellIsolated(Method method, const std::string& backend, int shell, int voxmap,
                               const BenchOptions& options);

/// The CSV of the cells (header + one line per cell).
/// The non-empty items of a comma-separated list ("128,256" -> {"128", "256"}): the sweep
/// options of `bmsim bench` and BMBenchCells.
std::vector<std::string> SplitCommaList(const std::string& s);

std::string BenchCsv(const std::vector<BenchCell>& cells);
/// Cells back from a bench.csv's text (BenchCsv's, or any CSV whose header names at least the
/// columns method, backend, shell, voxmap, status, median_ms, p99_ms and force_error; the other
/// BenchCell columns are read when present, unknown ones ignored), every row in file order.
/// `source` names the table in messages (default "bench.csv"). Throws std::runtime_error naming
/// the problem: an empty table, a missing column, a row with fewer fields than the header, a
/// value that is not a number or a method (with its line and column).
std::vector<BenchCell> ParseBenchCsv(const std::string& text,
                                     const std::string& source = "bench.csv");
/// A markdown table per backend laid out like the paper's Tables I/II: rows point-shell
/// resolution, columns voxmap resolution, "median (sd)" frame time in ms; then the p99 table.
std::string BenchTable(const std::vector<BenchCell>& cells, Method method, const std::string& title,
                       const std::vector<int>& shells, const std::vector<int>& voxmaps);

} // namespace bm
