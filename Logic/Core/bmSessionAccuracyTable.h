// bmSessionAccuracyTable.h - the session's accuracy table (`bmsim bench --session --accuracy`,
// Resources/Benchmark/session_accuracy.csv): per scene and voxmap, the frame p99 of the hand
// trial beside the offline reaming trial's outcome at that voxmap against a converged reference
// (bmReamingAccuracy.h). Read where a session's resolutions are chosen (bmSessionGrid.h) so that
// the choice says what accuracy it buys.
//
// CSV columns: scene, voxmap, shell, voxel_mm, view (0/1), p99_ms (0 for the reference's row),
// removed_mm3, face_depth_mm, face_angle_deg, seating (0..1), removed_error_pct,
// face_depth_error_mm, face_error_deg, seating_error_pct (percentage points), reference_voxmap,
// reference_shell, trial_s, machine, date.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace bm {

struct SessionAccuracyRow {
  std::string scene;
  int voxmap = 0, shell = 0;
  double voxelMm = 0; ///< mm
  bool view = false;  ///< the p99 was measured with the live view
  double p99Ms = 0;   ///< the hand trial's worst frame p99 on the incremental path, ms (0: none)
  double removedMm3 = 0, faceDepthMm = 0, faceAngleDeg = 0, seating = 0;
  double removedErrorPct = 0;  ///< against the reference, %
  double faceDepthErrorMm = 0; ///< mm
  double faceErrorDeg = 0;     ///< deg
  double seatingErrorPct = 0;  ///< percentage points
  int referenceVoxmap = 0, referenceShell = 0;
  double trialS = 0; ///< wall-clock time of the offline trial, s
  std::string machine, date;
};

std::string SessionAccuracyCsvHeader();
std::string SessionAccuracyCsvRecord(const SessionAccuracyRow& row);
/// Parses a table. Throws std::runtime_error naming `source`, the line and the column on a
/// missing column, a short record or a field that is not a number.
std::vector<SessionAccuracyRow> ParseSessionAccuracyCsv(const std::string& text,
                                                        const std::string& source);

/// $BM_SESSION_ACCURACY_CSV, else the resources' Benchmark/session_accuracy.csv.
std::string DefaultSessionAccuracyPath();
/// The table at DefaultSessionAccuracyPath(), or none (empty) when it is missing, not a plain
/// file or unreadable; `error` (optional) receives why.
std::vector<SessionAccuracyRow> LoadDefaultSessionAccuracy(std::string* error = nullptr);

/// What voxmap `voxmap` of scene `scene` buys: "its result against the converged reference
/// (voxmap R, v mm voxels): removed volume -4.8 %, the face's depth -0.22 mm and orientation
/// 0.53 deg, seating +0.4 points", or "" when the table has no row for that scene and voxmap.
std::string AccuracyBought(const std::vector<SessionAccuracyRow>& rows, const std::string& scene,
                           int voxmap);

} // namespace bm
