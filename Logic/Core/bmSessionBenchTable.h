// bmSessionBenchTable.h - measured frame times of haptic sessions on a scene (the hand-like trial
// of `bmsim bench --session`, Docs/Performance.md): what the panel's expected cost reads for a
// scene that has its own measurements, instead of the drilling bench's nearest cell.
//
// CSV columns (one row per scene, resolution, path, view and run): scene, voxmap, shell, threads,
// path ("incremental": the proxy's contact candidates and the engine's incremental pass; "full":
// every contact query scans the shell and the engine visits every element not culled), view
// (1: the live view refreshed the cut bone's surface every 33 ms meanwhile, 0: no view), run,
// frames, p50_ms, p99_ms, max_ms, over (frames over the period), overrun_pauses (pauses the
// default rule, > 5 of 100 frames over, would make), seconds (session time), machine, date,
// backend ("cpu" or "opencl"; optional when read: a table without it is the CPU backend's).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace bm {

struct SessionBenchRow {
  std::string scene;           ///< the scene's name (e.g. "glenoid")
  int voxmap = 0, shell = 0;   ///< cells along the longest side
  int threads = 0;             ///< engine threads
  std::string path;            ///< "incremental" or "full"
  bool view = false;           ///< the live view refreshed meanwhile
  int run = 0;                 ///< 1, 2, ... (repeats of the same cell)
  long long frames = 0;        ///< frames run
  double p50Ms = 0, p99Ms = 0; ///< frame time percentiles, ms
  double maxMs = 0;            ///< slowest frame, ms
  long long over = 0;          ///< frames over the haptic period
  long long overrunPauses = 0; ///< pauses the default overrun rule would make
  double seconds = 0;          ///< session time, s
  std::string machine, date;   ///< where and when it was measured (date YYYY-MM-DD)
  std::string backend = "cpu"; ///< the engine's backend
};

/// The CSV header line (no newline).
std::string SessionBenchCsvHeader();
/// One row as a CSV record (no newline); text fields are quoted.
std::string SessionBenchCsvRecord(const SessionBenchRow& row);
/// Parse a table. Throws std::runtime_error naming `source`, the line and the column on a missing
/// column, a short record, a field that is not a number, or a path other than incremental/full.
std::vector<SessionBenchRow> ParseSessionBenchCsv(const std::string& text,
                                                  const std::string& source);

/// The measured cell of `scene` on `path` with or without the view (`view`) nearest to (voxmap,
/// shell) (log distance, voxmap first), summarised over its runs: the worst p99 and max, the sums
/// of frames, over and pauses, and the median of the p50s. None when the scene has no row on that
/// path, or when the nearest cell's voxmap is more than `maxRatio` (default 1.5) times finer or
/// coarser: frame time grows steeply with resolution, so a far cell says little. threads > 0:
/// only rows measured with that many engine threads (default 0: any); backend: only its rows
/// (default "cpu").
std::optional<SessionBenchRow>
NearestSessionCell(const std::vector<SessionBenchRow>& rows, const std::string& scene, int voxmap,
                   int shell, bool view, const std::string& path = "incremental",
                   double maxRatio = 1.5, int threads = 0, const std::string& backend = "cpu");

/// $BM_SESSION_BENCHMARK_CSV, else the resources' Benchmark/session.csv.
std::string DefaultSessionBenchPath();

} // namespace bm
