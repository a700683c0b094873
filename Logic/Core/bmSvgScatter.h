// bmSvgScatter.h - a small scatter chart written as SVG text (no rendering library needed), e.g.
// predicted against measured forces with the identity line. Panels sit side by side; each has
// its own axes from 0 (or the data's minimum when negative) to the largest value, 5 ticks.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace bm {

struct ScatterSeries {
  std::string name;                          ///< legend text
  std::string color = "#1f77b4";             ///< SVG colour
  bool hollow = false;                       ///< ring markers instead of dots
  std::vector<std::array<double, 2>> points; ///< (x, y) in the panel's units
};

struct ScatterPanel {
  std::string title;
  std::string xLabel, yLabel; ///< with units, e.g. "measured thrust (N)"
  bool identityLine = true;   ///< draw y = x (same scale on both axes)
  std::vector<ScatterSeries> series;
};

/// The SVG document: panels left to right, each 360 x 360 px plus margins, a title on top.
/// Non-finite points are skipped.
std::string ScatterSvg(const std::vector<ScatterPanel>& panels, const std::string& title);

} // namespace bm
