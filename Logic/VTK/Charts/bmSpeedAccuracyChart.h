// bmSpeedAccuracyChart.h - the benchmark's speed-against-accuracy chart as a PNG
// (Docs/Performance.md).
//
// x: frame time (ms, log scale), y: an error (relative, log scale; the bench's force error, the
// session's removed-volume error); one series per method and
// backend, each point labelled by its resolutions ("shell/voxmap"), a vertical line at the haptic
// budget. Drawn with vtkChartXY in an off-screen vtkContextView; starts a private X server when
// DISPLAY is unset (bm::VirtualDisplay), since ParaView's VTK renders through GLX only.
#pragma once

#include <string>
#include <vector>

namespace bm {

struct ChartPoint {
  double x = 0;      ///< frame time, ms (> 0)
  double y = 0;      ///< force error, relative (> 0; smaller values are drawn at the floor)
  std::string label; ///< drawn next to the point
};

struct ChartSeries {
  std::string name; ///< legend entry, e.g. "lazar / cpu"
  std::vector<ChartPoint> points;
};

/// The bench's y axis: the force error.
constexpr const char* kForceErrorAxisTitle =
    "force error, max of |thrust| and |torque| relative error (log)";

/// Writes the chart to `pngPath` (width x height pixels, default 1400 x 900). budgetMs: where
/// the budget line is drawn (default 1 ms); yTitle: the y axis's title (default the force
/// error; y is relative, log scale). Throws std::runtime_error when rendering or writing fails or
/// there is no point to draw.
void WriteSpeedAccuracyChart(const std::string& pngPath, const std::string& title,
                             const std::vector<ChartSeries>& series, double budgetMs = 1.0,
                             int width = 1400, int height = 900,
                             const std::string& yTitle = kForceErrorAxisTitle);

} // namespace bm
