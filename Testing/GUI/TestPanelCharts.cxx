// qBMPanel's live charts: a history table handed to setHistory() is drawn. The thrust line is
// drawn in the chart's first series colour; with no history (or one row) no line is drawn.
// Run under Xvfb (Debian's VTK renders through GLX).
#include "qBMPanel.h"

#include "QVTKOpenGLNativeWidget.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkTable.h"

#include <QApplication>
#include <QImage>
#include <QSurfaceFormat>

#include <cmath>
#include <cstdio>

namespace {
/// Pixels of the chart that are neither white-ish background nor grey axes/text: the plotted
/// lines.
int ColouredPixels(QVTKOpenGLNativeWidget* chart) {
  const QImage image = chart->grabFramebuffer();
  int count = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QColor c = image.pixelColor(x, y);
      const int spread =
          std::max({c.red(), c.green(), c.blue()}) - std::min({c.red(), c.green(), c.blue()});
      count += spread > 60;
    }
  return count;
}

vtkNew<vtkTable> History(int rows) {
  vtkNew<vtkTable> table;
  for (const char* name : {"time_s", "thrust_N", "torque_Nmm", "frame_ms", "depth_mm"}) {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->SetNumberOfTuples(rows);
    table->AddColumn(column);
  }
  for (int i = 0; i < rows; ++i) {
    const double t = 0.01 * i;
    table->SetValue(i, 0, t);
    table->SetValue(i, 1, 10 + 5 * std::sin(10 * t));
    table->SetValue(i, 2, 20 + 3 * std::cos(7 * t));
    table->SetValue(i, 3, 0.2 + 0.05 * std::sin(30 * t));
    table->SetValue(i, 4, t);
  }
  return table;
}
} // namespace

int main(int argc, char* argv[]) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  qBMPanel panel;
  panel.resize(400, 1400);
  panel.show();
  app.processEvents();
  auto* force = panel.findChild<QVTKOpenGLNativeWidget*>("ForceChartWidget");
  auto* frame = panel.findChild<QVTKOpenGLNativeWidget*>("FrameChartWidget");
  if (!force || !frame) {
    std::fprintf(stderr, "FAIL: the panel has no ForceChartWidget / FrameChartWidget\n");
    return 1;
  }
  panel.setHistory(History(1));
  app.processEvents();
  const int emptyForce = ColouredPixels(force), emptyFrame = ColouredPixels(frame);
  panel.setHistory(History(300));
  app.processEvents();
  const int fullForce = ColouredPixels(force), fullFrame = ColouredPixels(frame);
  std::printf("coloured pixels: force chart %d -> %d, frame chart %d -> %d\n", emptyForce,
              fullForce, emptyFrame, fullFrame);
  // Two lines (thrust, torque) over 3 s and the frame time: hundreds of pixels each.
  if (fullForce < emptyForce + 200 || fullFrame < emptyFrame + 100) {
    std::fprintf(stderr, "FAIL: the history was not drawn\n");
    return 1;
  }
  panel.setHistory(nullptr);
  app.processEvents();
  if (ColouredPixels(force) > emptyForce + 20) {
    std::fprintf(stderr, "FAIL: the charts were not cleared\n");
    return 1;
  }
  std::printf("ok\n");
  return 0;
}
