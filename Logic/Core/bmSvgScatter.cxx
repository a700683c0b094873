#include "bmSvgScatter.h"
#include "bmHtmlEscape.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace bm {

namespace {

std::string Fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// A "nice" upper bound: 1, 2, 2.5 or 5 times a power of ten, >= v.
double NiceCeil(double v) {
  if (!(v > 0))
    return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= v * (1 - 1e-12))
      return m * p;
  return 10 * p;
}

} // namespace

std::string ScatterSvg(const std::vector<ScatterPanel>& panels, const std::string& title) {
  constexpr double kSize = 360, kLeft = 70, kRight = 20, kTop = 50, kBottom = 60, kLegend = 80;
  const double panelW = kLeft + kSize + kRight;
  const double width = panelW * double(std::max<size_t>(panels.size(), 1));
  const double height = kTop + kSize + kBottom + kLegend;
  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
     << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
     << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
     << "<text x=\"" << width / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">"
     << HtmlEscape(title) << "</text>\n";
  for (size_t p = 0; p < panels.size(); ++p) {
    const ScatterPanel& panel = panels[p];
    double lo = 0, hiX = 0, hiY = 0;
    for (const auto& s : panel.series)
      for (const auto& pt : s.points)
        if (std::isfinite(pt[0]) && std::isfinite(pt[1])) {
          lo = std::min({lo, pt[0], pt[1]});
          hiX = std::max(hiX, pt[0]);
          hiY = std::max(hiY, pt[1]);
        }
    if (panel.identityLine)
      hiX = hiY = std::max(hiX, hiY);
    hiX = NiceCeil(hiX);
    hiY = NiceCeil(hiY);
    const double loX = lo < 0 ? -NiceCeil(-lo) : 0.0, loY = loX;
    const double x0 = panelW * double(p) + kLeft, y0 = kTop + kSize;
    auto X = [&](double v) { return x0 + (v - loX) / (hiX - loX) * kSize; };
    auto Y = [&](double v) { return y0 - (v - loY) / (hiY - loY) * kSize; };
    os << "<g>\n<text x=\"" << x0 + kSize / 2 << "\" y=\"" << kTop - 10
       << "\" text-anchor=\"middle\" font-size=\"13\">" << HtmlEscape(panel.title) << "</text>\n";
    os << "<rect x=\"" << x0 << "\" y=\"" << kTop << "\" width=\"" << kSize << "\" height=\""
       << kSize << "\" fill=\"none\" stroke=\"#444\"/>\n";
    for (int t = 0; t <= 5; ++t) {
      const double vx = loX + (hiX - loX) * t / 5, vy = loY + (hiY - loY) * t / 5;
      os << "<line x1=\"" << X(vx) << "\" y1=\"" << y0 << "\" x2=\"" << X(vx) << "\" y2=\"" << kTop
         << "\" stroke=\"#ddd\"/>\n"
         << "<text x=\"" << X(vx) << "\" y=\"" << y0 + 16 << "\" text-anchor=\"middle\">" << Fmt(vx)
         << "</text>\n"
         << "<line x1=\"" << x0 << "\" y1=\"" << Y(vy) << "\" x2=\"" << x0 + kSize << "\" y2=\""
         << Y(vy) << "\" stroke=\"#ddd\"/>\n"
         << "<text x=\"" << x0 - 6 << "\" y=\"" << Y(vy) + 4 << "\" text-anchor=\"end\">" << Fmt(vy)
         << "</text>\n";
    }
    os << "<text x=\"" << x0 + kSize / 2 << "\" y=\"" << y0 + 38 << "\" text-anchor=\"middle\">"
       << HtmlEscape(panel.xLabel) << "</text>\n"
       << "<text transform=\"translate(" << x0 - 48 << "," << kTop + kSize / 2
       << ") rotate(-90)\" text-anchor=\"middle\">" << HtmlEscape(panel.yLabel) << "</text>\n";
    if (panel.identityLine) {
      const double a = std::max(loX, loY), b = std::min(hiX, hiY);
      os << "<line x1=\"" << X(a) << "\" y1=\"" << Y(a) << "\" x2=\"" << X(b) << "\" y2=\"" << Y(b)
         << "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
    }
    double legendY = y0 + 58;
    for (const auto& s : panel.series) {
      for (const auto& pt : s.points)
        if (std::isfinite(pt[0]) && std::isfinite(pt[1]))
          os << "<circle cx=\"" << X(pt[0]) << "\" cy=\"" << Y(pt[1]) << "\" r=\"4\" "
             << (s.hollow ? "fill=\"none\" stroke=\"" + s.color + "\" stroke-width=\"1.5\""
                          : "fill=\"" + s.color + "\"")
             << "/>\n";
      os << "<circle cx=\"" << x0 + 6 << "\" cy=\"" << legendY - 4 << "\" r=\"4\" "
         << (s.hollow ? "fill=\"none\" stroke=\"" + s.color + "\"" : "fill=\"" + s.color + "\"")
         << "/>\n<text x=\"" << x0 + 16 << "\" y=\"" << legendY << "\">" << HtmlEscape(s.name)
         << "</text>\n";
      legendY += 16;
    }
    os << "</g>\n";
  }
  os << "</svg>\n";
  return os.str();
}

} // namespace bm
