// The module panel's session and tool sections: the Pause button follows the session (it reads
// Resume, and is checked, while the session is paused, whether the user paused it or the session
// paused itself, and Pause otherwise); Start shows a busy indicator while a session is built; the
// Touch is probed off the GUI thread and its entry enabled only when ready; the wheel over the
// depth control steps the depth; the force scale shows its default; the CT section lists picked
// exclude points and refuses a malformed list; Save gives the bone file a
// voxmap extension; tool parameters have human labels with units and a tooltip each, and Add
// tool refuses invalid parameters.
#include "bmHapticSession.h"
#include "qBMCTWidget.h"
#include "qBMPanel.h"
#include "qBMSessionWidget.h"
#include "qBMToolWidget.h"
#include "qBMTouchProbe.h"

#include "QVTKOpenGLNativeWidget.h"

#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QSurfaceFormat>
#include <QAbstractSpinBox>
#include <QSlider>
#include <QWheelEvent>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace {
int failures = 0;
void Expect(bool ok, const char* what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAIL", what);
  failures += ok ? 0 : 1;
}
void Expect(bool ok, const std::string& what) {
  Expect(ok, what.c_str());
}

/// ParaView's WheelNeedsFocusBehavior (pqParaViewBehaviors.cxx, ParaView 5.11): an application
/// filter that eats the wheel events of spin boxes, combo boxes and sliders without the focus, so
/// that scrolling a panel does not change the values it passes over. Installed before the panel,
/// as ParaView installs it before loading plugins.
class WheelNeedsFocus : public QObject {
public:
  bool eventFilter(QObject* obj, QEvent* event) override {
    if (event->type() == QEvent::Wheel &&
        (qobject_cast<QAbstractSpinBox*>(obj) || qobject_cast<QComboBox*>(obj) ||
         qobject_cast<QSlider*>(obj)) &&
        !static_cast<QWidget*>(obj)->hasFocus())
      return true;
    return QObject::eventFilter(obj, event);
  }
};

void Wheel(QWidget* widget, int delta) {
  const QPointF at(widget->width() / 2.0, widget->height() / 2.0);
  QWheelEvent event(at, widget->mapToGlobal(at.toPoint()), QPoint(), QPoint(0, delta), Qt::NoButton,
                    Qt::NoModifier, Qt::NoScrollPhase, false);
  QApplication::sendEvent(widget, &event);
}
} // namespace

int main(int argc, char* argv[]) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  WheelNeedsFocus paraviewWheel;
  app.installEventFilter(&paraviewWheel);
  qBMPanel panel;
  qBMSessionWidget* session = panel.sessionWidget();
  // The Touch probe answers on the GUI thread, queued (BM_LIBHD names a missing library).
  {
    QSignalSpy answered(session->touchProbe(), &qBMTouchProbe::finished);
    Expect(answered.wait(10000) || !session->touchProbe()->isRunning(), "the probe answers");
  }
  auto* device = session->findChild<QComboBox*>("DeviceComboBox");
  auto* model = device ? qobject_cast<QStandardItemModel*>(device->model()) : nullptr;
  const int touchRow = device ? device->findText("Touch (OpenHaptics)") : -1;
  Expect(touchRow >= 0, "the device list has the Touch");
  std::printf("touch status: %s\n", session->touchStatus().toUtf8().constData());
  Expect(session->touchStatus().contains("/nonexistent/libHD.so"),
         "the probe names the missing library");
  Expect(model && touchRow >= 0 && !model->item(touchRow)->isEnabled(),
         "the Touch entry is disabled");
  // A probe that says ready enables the entry; one that throws is an answer too, not a crash.
  qBMTouchProbe* probe = session->touchProbe();
  probe->setProbeFunction([]() { return std::string(); });
  {
    QSignalSpy answered(probe, &qBMTouchProbe::finished);
    probe->start();
    Expect(probe->isRunning(), "the probe runs off the GUI thread (start() returned)");
    Expect(answered.wait(10000) && answered.at(0).at(0).toString().isEmpty(), "ready answers \"\"");
  }
  auto* touchLabel = session->findChild<QLabel*>("TouchStatusLabel");
  Expect(model && touchRow >= 0 && model->item(touchRow)->isEnabled() && touchLabel &&
             touchLabel->text() == "Touch: ready.",
         "a ready Touch enables its entry");
  {
    qBMTouchProbe failing;
    failing.setProbeFunction([]() -> std::string { throw std::runtime_error("no driver"); });
    QSignalSpy answered(&failing, &qBMTouchProbe::finished);
    failing.start();
    Expect(answered.wait(10000) &&
               answered.at(0).at(0).toString() == "touch probe failed: no driver",
           "a probe that throws answers why");
  }
  panel.show();
  app.processEvents();
  auto* pause = session->findChild<QPushButton*>("PauseButton");
  auto* start = session->findChild<QPushButton*>("StartButton");
  if (!pause || !start) {
    std::fprintf(stderr, "FAIL: the session section has no PauseButton or StartButton\n");
    return 1;
  }
  std::vector<bool> requests; // what pauseSessionRequested asked for
  QObject::connect(session, &qBMSessionWidget::pauseSessionRequested,
                   [&requests](bool paused) { requests.push_back(paused); });
  session->setSessionStatus("running", true);
  session->setSessionState(bm::SessionState::Running, "none");
  Expect(pause->text() == "Pause" && !pause->isChecked(), "a running session shows Pause");
  Expect(!start->isEnabled(), "a running session: Start is disabled");
  pause->click(); // the user pauses
  Expect(pause->text() == "Resume" && pause->isChecked(), "after a click the button reads Resume");
  Expect(requests.size() == 1 && requests[0], "the click asked to pause");
  pause->click(); // and resumes
  Expect(pause->text() == "Pause" && !pause->isChecked(), "a second click reads Pause again");
  Expect(requests.size() == 2 && !requests[1], "the second click asked to resume");
  session->setSessionState(bm::SessionState::Paused, "overrun"); // the session paused itself
  Expect(pause->text() == "Resume" && pause->isChecked(), "a self-paused session reads Resume");
  Expect(start->isEnabled(), "a paused session can be replaced: Start is enabled");
  auto* state = session->findChild<QLabel*>("SessionStateLabel");
  Expect(state && state->text() == "Session paused: overrun", "the state names the reason");
  Expect(requests.size() == 2, "showing the state requests nothing");
  session->setSessionState(bm::SessionState::Running, "none");
  Expect(pause->text() == "Pause" && !pause->isChecked(), "running again reads Pause");
  Expect(!start->isEnabled(), "running again: Start is disabled again");
  session->setSessionState(bm::SessionState::Paused, "device error");
  session->setSessionStatus("stopped", false);
  Expect(pause->text() == "Pause" && !pause->isChecked() && !pause->isEnabled(),
         "a stopped session resets the button");
  // Start's progress: a busy indicator and the status while the bone is built.
  auto* progress = session->findChild<QProgressBar*>("StartProgressBar");
  Expect(progress && !progress->isVisible() && start->isEnabled(), "not busy: no indicator");
  session->setBusy(true, "Building BMSession1's bone and tool...");
  Expect(progress && progress->isVisible() && !start->isEnabled() &&
             session->sessionStatus() == "Building BMSession1's bone and tool...",
         "busy: the indicator shows, Start is disabled and the status says why");
  session->setBusy(false);
  Expect(progress && !progress->isVisible() && start->isEnabled(), "done: the indicator goes");
  // The wheel over the depth control moves the depth (0.1 mm a notch) and is not passed on: while
  // a mouse-proxy session runs without a click on the control first (ParaView's filter above eats
  // wheels without the focus); with no session it is ParaView's rule, so scrolling the panel past
  // the control leaves the depth as it was.
  auto* depth = session->findChild<QDoubleSpinBox*>("ToolDepthSpinBox");
  auto* devices = session->findChild<QComboBox*>("DeviceComboBox");
  QSignalSpy depthChanged(session, &qBMSessionWidget::toolDepthChanged);
  if (depth && devices) {
    Expect(!depth->hasFocus(), "the depth control has not the focus");
    Wheel(depth, 120);
    Expect(session->toolDepth() == -2.0 && depthChanged.count() == 0,
           "no session: a wheel passing over the depth control leaves it");
    devices->setCurrentIndex(devices->findText("Mouse proxy"));
    session->setSessionStatus("Started BMSession1.", true);
    Wheel(depth, 120);
    Expect(std::abs(session->toolDepth() - (-1.9)) < 1e-9 && depthChanged.count() == 1,
           "a wheel notch deepens the proxy by 0.1 mm");
    session->setToolDepth(20.0);
    Wheel(depth, 120);
    Expect(session->toolDepth() == 20.0, "at the end of the range the depth stays");
  } else {
    Expect(false, "the session section has a ToolDepthSpinBox");
  }
  Expect(session->forceScale() == 0.0, "the force scale defaults to 0, the tool's");
  if (auto* scale = session->findChild<QDoubleSpinBox*>("ForceScaleSpinBox"))
    Expect(scale->text() == "per tool",
           "the default force scale reads 'per tool', not '" + scale->text().toStdString() + "'");
  else
    Expect(false, "the session section has a ForceScaleSpinBox");
  session->setSessionNumbers(1.0, 0.5, 2.0, 10.0, 20.0, 0.4, 6.0);
  if (auto* numbers = session->findChild<QLabel*>("SessionNumbersLabel"))
    Expect(numbers->text().endsWith("force scale 6"),
           "the session's numbers name the force scale in use: " + numbers->text().toStdString());
  else
    Expect(false, "the session section has a SessionNumbersLabel");
  session->setForceScale(5000.0);
  Expect(session->forceScale() == 1000.0, "the force scale is clamped to 1000");
  // Save gives a name without an extension the voxmap's.
  QSignalSpy saved(session, &qBMSessionWidget::saveBoneRequested);
  session->setBoneFile("/tmp/cut");
  if (auto* save = session->findChild<QPushButton*>("SaveBoneButton"))
    save->click();
  Expect(saved.count() == 1 && saved.at(0).at(0).toString() == "/tmp/cut.nrrd" &&
             session->boneFile() == "/tmp/cut.nrrd",
         "Save adds .nrrd");
  // The CT section's exclude points and include seed, as the 3D view's picks give them.
  qBMCTWidget* ct = panel.ctWidget();
  ct->addExcludePoint(1, 2, 3);
  ct->addExcludePoint(4, 5.5, -6);
  QVector<double> exclude;
  QString excludeError;
  Expect(ct->excludePointsText() == "1.00 2.00 3.00; 4.00 5.50 -6.00" &&
             ct->excludePoints(exclude, excludeError) &&
             exclude == QVector<double>({1, 2, 3, 4, 5.5, -6}),
         "picked exclude points are listed and read back");
  ct->setExcludePointsText("1 2");
  Expect(!ct->excludePoints(exclude, excludeError) && exclude.isEmpty() &&
             excludeError.contains("point 1"),
         "a malformed list is refused naming the point");
  Expect(!ct->useSeed(), "no include seed by default");
  ct->setSeed({7, 8, 9});
  Expect(ct->useSeed() && ct->seed() == QVector<double>({7, 8, 9}), "a picked seed is kept");
  Expect(!ct->useBox() && ct->boxHalfSizes() == QVector<double>({50, 50, 50}),
         "no oriented box by default, half sizes 50 mm");
  ct->setBox({1, 2, 3}, {4, 5, 6}, {10, 20, 30});
  Expect(ct->useBox() && ct->boxCentre() == QVector<double>({1, 2, 3}) &&
             ct->boxHalfSizes() == QVector<double>({4, 5, 6}) &&
             ct->boxRotation() == QVector<double>({10, 20, 30}),
         "the oriented box is set and read back");
  // Tool parameters: a label with its unit and a tooltip each.
  qBMToolWidget* tool = panel.toolWidget();
  tool->setToolType(1); // the reamer
  auto* arc = tool->findChild<QDoubleSpinBox*>("arc_centre_offset_mm");
  auto* nipple = tool->findChild<QDoubleSpinBox*>("nipple_radius_mm");
  auto* lipsBox = tool->findChild<QSpinBox*>("lips");
  bool labelled = false;
  for (QLabel* label : tool->findChildren<QLabel*>())
    labelled = labelled || (label->buddy() == arc && label->text() == "Arc centre offset (mm):");
  Expect(arc && labelled, "a label with its unit");
  Expect(nipple && lipsBox && nipple->toolTip() != lipsBox->toolTip() &&
             nipple->toolTip().contains("mm"),
         "a tooltip of its own");
  // Add tool with invalid parameters adds nothing and says why.
  int added = 0;
  QObject::connect(tool, &qBMToolWidget::addToolRequested, [&added](int, int) { ++added; });
  auto* add = tool->findChild<QPushButton*>("AddToolButton");
  Expect(add && lipsBox, "the tool section has AddToolButton and a lips editor");
  if (add && lipsBox) {
    add->click();
    Expect(added == 1, "a valid tool is added");
    lipsBox->setValue(0);
    add->click();
    Expect(added == 1 && tool->statusMessage().contains("lips"),
           "an invalid tool is refused, naming the parameter");
  }
  return failures == 0 ? 0 : 1;
}
