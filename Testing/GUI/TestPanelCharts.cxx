// The module panel's live charts (qBMChartsWidget): a history table handed to setHistory() is
// drawn; with no history (or one row) no line is drawn. The charts keep their rows across
// updates whose window has moved on (a pause, the session's 10 s window), a new session (time
// going back) starts them again, and frames over the period are counted and marked.
// Run under Xvfb (Debian's VTK renders through GLX).
#include "qBMChartsWidget.h"
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

vtkNew<vtkTable> History(int rows, int first = 0, int overrunEvery = 0) {
  vtkNew<vtkTable> table;
  for (const char* name : {"time_s", "thrust_N", "torque_Nmm", "frame_ms", "depth_mm"}) {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->SetNumberOfTuples(rows);
    table->AddColumn(column);
  }
  for (int i = 0; i < rows; ++i) {
    const double t = 0.01 * (first + i);
    table->SetValue(i, 0, t);
    table->SetValue(i, 1, 10 + 5 * std::sin(10 * t));
    table->SetValue(i, 2, 20 + 3 * std::cos(7 * t));
    const bool overrun = overrunEvery > 0 && (first + i) % overrunEvery == 0;
    table->SetValue(i, 3, overrun ? 1.5 : 0.2 + 0.05 * std::sin(30 * t));
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
  qBMChartsWidget* charts = panel.chartsWidget();
  charts->setHistory(History(1));
  app.processEvents();
  const int emptyForce = ColouredPixels(force), emptyFrame = ColouredPixels(frame);
  charts->setHistory(History(300));
  app.processEvents();
  const int fullForce = ColouredPixels(force), fullFrame = ColouredPixels(frame);
  std::printf("coloured pixels: force chart %d -> %d, frame chart %d -> %d\n", emptyForce,
              fullForce, emptyFrame, fullFrame);
  // Two lines (thrust, torque) over 3 s and the frame time: hundreds of pixels each.
  if (fullForce < emptyForce + 200 || fullFrame < emptyFrame + 100) {
    std::fprintf(stderr, "FAIL: the history was not drawn\n");
    return 1;
  }
  charts->setHistory(nullptr);
  app.processEvents();
  if (ColouredPixels(force) > emptyForce + 20 || charts->historyRows() != 0) {
    std::fprintf(stderr, "FAIL: the charts were not cleared\n");
    return 1;
  }
  // The session's window moves on (rows 0-299, then 200-499 after a pause): the charts keep all.
  charts->setHistory(History(300, 0, 50));
  charts->setHistory(History(300, 200, 50));
  std::printf("rows %d, overruns %d, title '%s'\n", charts->historyRows(), charts->overrunRows(),
              charts->frameChartTitle().toUtf8().constData());
  if (charts->historyRows() != 500 || charts->overrunRows() != 10 ||
      charts->frameChartTitle() != "Haptic frame time (ms): 10 over the 1 ms period") {
    std::fprintf(stderr, "FAIL: the history across the pause or its overruns\n");
    return 1;
  }
  charts->setHistory(History(100)); // a new session: its time went back
  if (charts->historyRows() != 100 || charts->overrunRows() != 0) {
    std::fprintf(stderr, "FAIL: a new session did not start the charts again\n");
    return 1;
  }
  std::printf("ok\n");
  return 0;
}
