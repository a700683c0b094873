// bmPanelLogic.h - what the BoneMachining panel shows that is computed, without Qt: tool
// parameter labels and tooltips with their units, the bone file's extension, the session state as
// words, the force scale's range, and the expected cost of a session's resolutions (from the
// measured benchmark table, bmBenchmarkTable.h). The Widgets/ panels display these strings and
// compute nothing themselves (Docs/Plugin.md).
//
// Units: mm, deg, rpm, N (in the parameter keys' suffixes); ms and % in the expected cost; the
// force scale is tool N per device N.
#pragma once

#include "bmBenchmarkTable.h"

#include <optional>
#include <string>
#include <vector>

namespace bm {

enum class SessionState;   // bmHapticSession.h: Idle, Running, Paused, Stopped
struct SessionBenchRow;    // bmSessionBenchTable.h: a measured session cell
struct SessionAccuracyRow; // bmSessionAccuracyTable.h: what a session voxmap buys

namespace PanelLogic {

/// A tool parameter's label for a key of the tool specification (bmToolModel.h): words and the
/// unit from the key's suffix, e.g. "arc_centre_offset_mm" -> "Arc centre offset (mm)",
/// "alpha_deg" -> "Alpha (deg)", "lips" -> "Lips".
std::string ParameterLabel(const std::string& key);
/// What a tool parameter is, with its unit, for its tooltip (one per known key; "Tool parameter:
/// <label>" for others).
std::string ParameterToolTip(const std::string& key);

/// The CT file dialog's filter: "CT volumes (*.nrrd ... *.vti *.vtk);;All files (*)", every file
/// type the CT import reads (bm::CTFileExtensions, bm::VTKImageExtensions).
std::string CTFileFilter();

/// `path` with a voxmap extension: a name without any extension gets "." + defaultSuffix
/// (default "nrrd"); a name with an extension is returned unchanged (the save refuses formats
/// other than .nrrd and .mha, naming them), and so is "". A dot in a folder name is not an
/// extension.
std::string WithVoxmapExtension(const std::string& path, const std::string& defaultSuffix = "nrrd");

/// Reads a list of points (world mm) as typed in the panel: points separated by ';', each three
/// numbers separated by spaces or commas, e.g. "10 0 -5; 12.5, 3, -5". Empty text (or only
/// blanks) is no points. Returns "" and fills `xyz` (x y z per point) or, for malformed text,
/// leaves it empty and returns why, naming the point: "point 2 ('4 5'): give three numbers x y
/// z (mm)".
std::string ParsePoints(const std::string& text, std::vector<double>& xyz);

/// The session state in words: "" (Idle), "running", "paused: <reason>" ("paused" when the
/// reason is empty), "stopped". `reason` is bm::ToString(PauseReason), e.g. "overrun".
std::string StateText(SessionState state, const std::string& pauseReason);
/// Whether the Pause button reads Resume: the session is paused (by the user or by itself).
bool IsPaused(SessionState state);
/// Whether the session holds the device and its thread (Running or Paused): Pause and Stop are
/// enabled, Start is not.
bool IsActive(SessionState state);

/// Force scale (tool N per device N): the accepted range [1e-3, 1000] (bm::CheckForceScale) and
/// the panel's default, 0: the tool's (bm::SessionForceScale).
double MinForceScale();
double MaxForceScale();
double DefaultForceScale();
/// "" when `scale` is a valid force scale, else why not (naming the accepted range).
std::string ForceScaleError(double scale);

/// The expected frame time and force error of a session's resolutions: the nearest measured
/// cell of the benchmark table for the scene's method and backend.
class ExpectedCost {
public:
  ~ExpectedCost();
  ExpectedCost(ExpectedCost&&) noexcept;
  ExpectedCost& operator=(ExpectedCost&&) noexcept;
  /// Reads the drilling bench table at bm::BenchmarkTable::DefaultPath() ($BM_BENCHMARK_CSV or
  /// the resources') and the session table at bm::DefaultSessionBenchPath()
  /// ($BM_SESSION_BENCHMARK_CSV or the resources' Benchmark/session.csv); a bench table that
  /// cannot be read is remembered and named by Line(); without a session table every scene uses
  /// the bench.
  ExpectedCost();
  /// Uses `table`, `sessions` and `accuracy` (tests).
  explicit ExpectedCost(BenchmarkTable table, std::vector<SessionBenchRow> sessions = {},
                        std::vector<SessionAccuracyRow> accuracy = {});
  /// One line for the panel. For a scene with its own session measurements near the asked
  /// resolution (a hand-like trial of `bmsim bench --session`, on the scene's own method, voxmap
  /// within 1.5 x; bm::NearestSessionCell): "Expected (<scene> session, shell S /
  /// voxmap V, nearest measured: s / v, hand-like trial with the live view on <machine>, <date>)
  /// (measurements with the view first, else "without the view"): frame <p50> ms
  /// median, <p99> ms p99, <max> ms max; <N> overrun pauses in <T> s; force error <e> %[; its
  /// result against the converged reference ...]" (the force error from the bench's cell; the
  /// accuracy from the session accuracy table at bm::DefaultSessionAccuracyPath() when it has the
  /// voxmap, bm::AccuracyBought). Otherwise: "Expected (<method>, shell S / voxmap V,
  /// nearest measured: s / v): frame <median> ms median, <p99> ms p99; force error <e> %" from
  /// the drilling bench, or why it is unknown (an unreadable table, an unknown scene, no cell of
  /// that method and backend).
  /// `scene`: a built-in name or a scene file; `voxmap`, `shell`: cells along the longest side,
  /// 0 = the scene's (a voxmap set alone scales the scene's shell alike, as the session does);
  /// `method`: a vtkBMSessionSource::MethodTypes value (0 the scene's, 1 Lazar, 2 Zheng).
  /// When the p99 frame time exceeds `periodMs` (the haptic period, ms; default 1, i.e. 1 kHz),
  /// or the measured session paused on overruns, the line ends with a warning that the session
  /// will pause on overruns.
  std::string Line(const std::string& scene, int voxmap, int shell, int method,
                   double periodMs = 1.0) const;

private:
  std::optional<BenchmarkTable> Table_;
  std::string Error_;
  std::vector<SessionBenchRow> Sessions_;
  std::vector<SessionAccuracyRow> Accuracy_;
};

} // namespace PanelLogic
} // namespace bm
