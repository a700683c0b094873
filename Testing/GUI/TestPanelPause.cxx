// qBMPanel's Pause button follows the session: it reads Resume (and is checked) while the session
// is paused, whether the user paused it or the session paused itself, and Pause otherwise.
#include "qBMPanel.h"

#include "QVTKOpenGLNativeWidget.h"

#include <QApplication>
#include <QPushButton>
#include <QSurfaceFormat>

#include <cstdio>
#include <vector>

namespace {
int failures = 0;
void Expect(bool ok, const char* what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAIL", what);
  failures += ok ? 0 : 1;
}
} // namespace

int main(int argc, char* argv[]) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  qBMPanel panel;
  panel.show();
  app.processEvents();
  auto* pause = panel.findChild<QPushButton*>("PauseButton");
  if (!pause) {
    std::fprintf(stderr, "FAIL: the panel has no PauseButton\n");
    return 1;
  }
  std::vector<bool> requests; // what pauseSessionRequested asked for
  QObject::connect(&panel, &qBMPanel::pauseSessionRequested,
                   [&requests](bool paused) { requests.push_back(paused); });
  panel.setSessionStatus("running", true);
  panel.setSessionState("running");
  Expect(pause->text() == "Pause" && !pause->isChecked(), "a running session shows Pause");
  pause->click(); // the user pauses
  Expect(pause->text() == "Resume" && pause->isChecked(), "after a click the button reads Resume");
  Expect(requests.size() == 1 && requests[0], "the click asked to pause");
  pause->click(); // and resumes
  Expect(pause->text() == "Pause" && !pause->isChecked(), "a second click reads Pause again");
  Expect(requests.size() == 2 && !requests[1], "the second click asked to resume");
  panel.setSessionState("paused: overrun"); // the session paused itself
  Expect(pause->text() == "Resume" && pause->isChecked(), "a self-paused session reads Resume");
  Expect(requests.size() == 2, "showing the state requests nothing");
  panel.setSessionState("running");
  Expect(pause->text() == "Pause" && !pause->isChecked(), "running again reads Pause");
  panel.setSessionState("paused: device error");
  panel.setSessionStatus("stopped", false);
  Expect(pause->text() == "Pause" && !pause->isChecked() && !pause->isEnabled(),
         "a stopped session resets the button");
  return failures == 0 ? 0 : 1;
}
