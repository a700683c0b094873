// bmReportCharts.h - line charts of a run (thrust, torque, frame time over time) as PNG images
// (the benchmark's scatter chart is Logic/VTK/Charts/bmSpeedAccuracyChart.h),
// drawn with VTK's charts (vtkChartXY in a vtkContextView) off screen.
//
// Rendering needs an X display (Debian's ParaView VTK renders through GLX only):
// WriteLineChartPng calls bm::VirtualDisplay::Ensure() first, which starts a private Xvfb when
// DISPLAY is unset.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace bm {

struct LineSeries {
  std::string name;      ///< legend entry
  std::vector<double> y; ///< one value per x
  std::array<unsigned char, 3> rgb{31, 119, 180};
};

struct LineChart {
  std::string title;
  std::string xLabel, yLabel; ///< axis titles, units included, e.g. "time (s)"
  std::vector<double> x;
  std::vector<LineSeries> series;
  int widthPx = 900, heightPx = 420;
};

/// Draws `chart` and writes it to `path` as PNG (atomically). Series longer than x are cut to
/// x's length. Throws std::runtime_error when there is nothing to draw or the file cannot be
/// written.
void WriteLineChartPng(const std::string& path, const LineChart& chart);

} // namespace bm
