// qBMPanel's session controls: the Pause button follows the session (it reads Resume, and is
// checked, while the session is paused, whether the user paused it or the session paused itself,
// and Pause otherwise), Save gives the bone file a voxmap extension, and tool parameters have
// human labels with units and a tooltip each, and Add tool refuses invalid parameters.
#include "qBMPanel.h"

#include "QVTKOpenGLNativeWidget.h"

#include <QApplication>
#include <QPushButton>
#include <QSpinBox>
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
  Expect(qBMPanel::withVoxmapExtension("/tmp/cut") == "/tmp/cut.nrrd", "no extension: .nrrd");
  Expect(qBMPanel::withVoxmapExtension("/tmp/cut", "mha") == "/tmp/cut.mha",
         "the MHA filter: .mha");
  Expect(qBMPanel::withVoxmapExtension("/tmp/cut.MHA") == "/tmp/cut.MHA", "an extension is kept");
  Expect(qBMPanel::withVoxmapExtension("/tmp/cut.txt") == "/tmp/cut.txt",
         "another extension is left for the save to refuse");
  Expect(qBMPanel::withVoxmapExtension("/tmp/a.b/cut") == "/tmp/a.b/cut.nrrd",
         "a dot in a folder name is not an extension");
  Expect(qBMPanel::withVoxmapExtension("").isEmpty(), "no name stays empty");
  Expect(qBMPanel::parameterLabel("arc_centre_offset_mm") == "Arc centre offset (mm)",
         "a label with its unit");
  Expect(qBMPanel::parameterLabel("alpha_deg") == "Alpha (deg)", "degrees");
  Expect(qBMPanel::parameterLabel("lips") == "Lips", "no unit");
  Expect(qBMPanel::parameterToolTip("nipple_radius_mm") != qBMPanel::parameterToolTip("lips") &&
             qBMPanel::parameterToolTip("nipple_radius_mm").contains("mm"),
         "a tooltip of its own");
  // Add tool with invalid parameters adds nothing and says why.
  int added = 0;
  QObject::connect(&panel, &qBMPanel::addToolRequested, [&added](int, int) { ++added; });
  auto* add = panel.findChild<QPushButton*>("AddToolButton");
  auto* lips = panel.findChild<QSpinBox*>("lips");
  Expect(add && lips, "the panel has AddToolButton and a lips editor");
  if (add && lips) {
    add->click();
    Expect(added == 1, "a valid tool is added");
    lips->setValue(0);
    add->click();
    Expect(added == 1 && panel.statusMessage().contains("lips"),
           "an invalid tool is refused, naming the parameter");
  }
  return failures == 0 ? 0 : 1;
}
