// bmCalibrationData.h - measured drilling/reaming forces as a CSV file, read into calibration
// samples (bmCalibration.h). One row per measurement; the header names the columns, in any order:
//
//   tool             drill | reamer | burr                                         (required)
//   diameter_mm      tool diameter, mm (default: the tool type's default)
//   point_angle_deg  drill point angle, full included angle, deg (default 118)
//   helix_angle_deg  drill helix angle, deg (default 20)
//   web_half_width_mm  drill half chisel-edge width, mm (default 0.2)
//   feed_mm_per_rev  feed per revolution, mm/rev                                   (required)
//   speed_rpm        spindle speed, rpm                                            (required)
//   bone             bone or specimen label (bone factors are fitted per label)
//   density          known density scale of k_c, k_t (the engine's voxel material; default 1)
//   depth_mm         depth from the foremost cutting point, mm (empty = fully engaged)
//   thrust_N         measured thrust, N                                            (required)
//   torque_Nmm       measured torque, N mm (empty = not measured)
//   source           citation of the row
//   note             how the numbers were obtained (table, text, read off a figure, assumed)
//
// Fields may be quoted ("a, b"); "" inside quotes is a quote. Lines starting with # are comments.
// A condition (cross-validation group) is one tool geometry, feed, speed and bone.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bmCalibration.h"

namespace bm {

struct CalibrationRecord {
  CalibrationSample sample;
  nlohmann::json toolSpec; ///< MakeTool's JSON of the row's tool
  std::string source;      ///< the row's citation
  std::string note;        ///< how the row's numbers were obtained
  int line = 0;            ///< line in the file (1-based)
};

/// Reads a calibration CSV. Throws std::invalid_argument naming the file, line and column of the
/// first bad field (unknown column, missing required value, malformed or out-of-range number).
std::vector<CalibrationRecord> ReadCalibrationCsv(const std::filesystem::path& file);

/// Writes records in the column layout ReadCalibrationCsv reads (numbers at full precision).
std::string FormatCalibrationCsv(const std::vector<CalibrationRecord>& records);

/// The samples of the records, in order.
std::vector<CalibrationSample> SamplesOf(const std::vector<CalibrationRecord>& records);

} // namespace bm
