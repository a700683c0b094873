// bmSvgScatter.h: one marker per finite point plus one per legend entry, text escaped, panels
// side by side.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "bmSvgScatter.h"

namespace {

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

TEST(SvgScatter, OneMarkerPerFinitePointAndLegendEntry) {
  bm::ScatterPanel a{"thrust <N>", "measured (N)", "predicted (N)", true, {}};
  a.series.push_back({"fit & check", "#1f77b4", false, {{1, 1.1}, {2, 1.9}, {NAN, 3}}});
  a.series.push_back({"held out", "#d62728", true, {{3, 2.5}}});
  bm::ScatterPanel b{"torque", "measured (N mm)", "predicted (N mm)", false, {}};
  b.series.push_back({"fit", "#1f77b4", false, {{10, 12}, {20, 18}, {30, 33}}});
  const std::string svg = bm::ScatterSvg({a, b}, "title");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // 2 + 1 + 3 finite points, 3 legend markers; the NaN point is skipped.
  EXPECT_EQ(Count(svg, "<circle"), 9u);
  EXPECT_NE(svg.find("thrust &lt;N&gt;"), std::string::npos);
  EXPECT_NE(svg.find("fit &amp; check"), std::string::npos);
  EXPECT_EQ(svg.find("thrust <N>"), std::string::npos);
  EXPECT_EQ(Count(svg, "stroke-dasharray"), 1u); // the identity line of the first panel only
  EXPECT_NE(svg.find("width=\"900\""), std::string::npos); // two 450 px panels
}

} // namespace
