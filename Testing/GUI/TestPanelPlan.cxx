// The module panel's Planning section over the BM Glenoid Plan filter on the scapula phantom's
// voxmap (1 mm, no CT): Plan shows the measured angles (within 1 deg of the phantom's truth) and
// fills the landmarks in with the detected points; moving the trigonum (as its handle in the 3D
// view does: setLandmark) turns Friedman's scapular axis 5 deg and the shown Friedman version
// changes by 5 deg; without a CT the step buttons stay disabled; a bone without a glenoid shows "no
// glenoid found". The section is driven as the dock drives it: planRequested -> the filter's
// settings -> setPlanResult / setPlanFailure.
#include "qBMPanel.h"
#include "qBMPlanWidget.h"
#include "vtkBMGlenoidPlanFilter.h"

#include "bmBoneFractionImage.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"

#include "vtkImageData.h"
#include "vtkNew.h"

#include <QApplication>
#include <QCheckBox>
#include <QLabel>
#include <QPushButton>

#include <cmath>
#include <cstdio>

namespace {
int failures = 0;
void Expect(bool ok, const QString& what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAIL", what.toUtf8().constData());
  failures += ok ? 0 : 1;
}

/// The number a label shows ("-11.7 deg" -> -11.7); NaN when it shows none.
double Shown(const QWidget* root, const char* name) {
  const auto* label = root->findChild<QLabel*>(name);
  if (!label)
    return NAN;
  bool ok = false;
  const double v = label->text().section(' ', 0, 0).toDouble(&ok);
  return ok ? v : NAN;
}

/// What the dock does on planRequested: the section's settings onto the filter, its result back.
void Plan(qBMPlanWidget* w, vtkBMGlenoidPlanFilter* f) {
  const QVector<double> c = w->landmark(0), t = w->landmark(1), i = w->landmark(2);
  f->SetUseGlenoidCentre(w->useLandmark(0));
  f->SetGlenoidCentre(c[0], c[1], c[2]);
  f->SetUseTrigonum(w->useLandmark(1));
  f->SetTrigonum(t[0], t[1], t[2]);
  f->SetUseInferiorAngle(w->useLandmark(2));
  f->SetInferiorAngle(i[0], i[1], i[2]);
  const QVector<double> n = w->landmark(3);
  f->SetUseFaceNormal(w->useLandmark(3));
  f->SetFaceNormal(n[0], n[1], n[2]);
  f->SetTargetVersion(w->targetVersion());
  f->SetTargetInclination(w->targetInclination());
  f->SetReamDepth(w->reamDepth());
  f->SetReamerDiameter(w->reamerDiameter());
  f->Update();
  if (*f->GetLastError()) {
    w->setPlanFailure(QString::fromUtf8(f->GetLastError()));
    return;
  }
  auto vec = [](const double* p) { return QVector<double>{p[0], p[1], p[2]}; };
  qBMPlanResult r;
  r.friedmanVersionDeg = f->GetFriedmanVersion();
  r.version3DDeg = f->GetVersion3D();
  r.inclinationDeg = f->GetInclination();
  r.heightMm = f->GetGlenoidHeight();
  r.widthMm = f->GetGlenoidWidth();
  r.faceRadiusMm = f->GetFaceRadius();
  r.correctionDeg = f->GetCorrection();
  r.reamerFits = f->GetReamerFits() != 0;
  r.glenoidCentre = vec(f->GetUsedGlenoidCentre());
  r.trigonum = vec(f->GetUsedTrigonum());
  r.inferiorAngle = vec(f->GetUsedInferiorAngle());
  r.faceNormal = vec(f->GetUsedFaceNormal());
  r.entry = vec(f->GetPlanEntry());
  r.axis = vec(f->GetPlanAxis());
  const QString warnings = QString::fromUtf8(f->GetWarnings());
  if (!warnings.isEmpty())
    r.warnings = warnings.split('\n');
  r.canRunSteps = *f->GetPlanScene() != '\0';
  w->setPlanResult(r);
}
} // namespace

int main(int argc, char* argv[]) {
  QApplication app(argc, argv);
  qBMPanel panel;
  qBMPlanWidget* plan = panel.planWidget();
  Expect(plan && plan->objectName() == "PlanGroupBox", "the panel has a Planning section");
  if (!plan)
    return 1;

  const bm::ScapulaPhantom phantom{bm::ScapulaPhantomParams{}};
  const bm::ScapulaTruth& truth = phantom.Truth();
  bm::BoneFractionImage image;
  image.Update(bm::MakeScapulaVoxmap(phantom, 1.0, 3));
  vtkNew<vtkBMGlenoidPlanFilter> filter;
  filter->SetInputData(image.GetOutput());
  QObject::connect(plan, &qBMPlanWidget::planRequested, [&]() { Plan(plan, filter); });

  plan->findChild<QPushButton*>("PlanButton")->click();
  const double friedman = Shown(plan, "FriedmanVersionLabel");
  const double version = Shown(plan, "Version3DLabel");
  const double inclination = Shown(plan, "InclinationLabel");
  Expect(std::abs(friedman - truth.friedmanVersionDeg) < 1.0,
         QString("Friedman version shown %1 deg (truth %2)")
             .arg(friedman)
             .arg(truth.friedmanVersionDeg));
  Expect(std::abs(version - truth.version3DDeg) < 1.0,
         QString("3D version shown %1 deg (truth %2)").arg(version).arg(truth.version3DDeg));
  Expect(std::abs(inclination - truth.inclinationDeg) < 1.0,
         QString("inclination shown %1 deg (truth %2)").arg(inclination).arg(truth.inclinationDeg));
  const QVector<double> trigonum = plan->landmark(1);
  Expect(std::hypot(trigonum[0] - truth.trigonum[0], trigonum[1] - truth.trigonum[1],
                    trigonum[2] - truth.trigonum[2]) < 3.0,
         "the trigonum's fields hold the detected trigonum");
  Expect(!plan->findChild<QPushButton*>("RunPinButton")->isEnabled(),
         "no CT named: the guide-pin step cannot run");

  // Drag the trigonum 5 deg about the vertical through the midpoint of Friedman's glenoid line
  // (where his scapular axis from the trigonum ends).
  const double* line = filter->GetGlenoidLine();
  const double mx = (line[0] + line[3]) / 2, my = (line[1] + line[4]) / 2;
  const double a = 5.0 * 3.14159265358979323846 / 180, x = trigonum[0] - mx, y = trigonum[1] - my;
  plan->setLandmark(1, {mx + std::cos(a) * x - std::sin(a) * y,
                        my + std::sin(a) * x + std::cos(a) * y, trigonum[2]});
  Expect(plan->findChild<QCheckBox*>("UseTrigonumCheckBox")->isChecked(),
         "a moved trigonum is used");
  const double moved = Shown(plan, "FriedmanVersionLabel");
  Expect(std::abs(std::abs(moved - friedman) - 5.0) < 0.15,
         QString("the shown Friedman version follows the trigonum: %1 -> %2 deg")
             .arg(friedman)
             .arg(moved));
  Expect(std::abs(Shown(plan, "Version3DLabel") - version) > 1.0, "the 3D version changes too");
  Expect(filter->GetDetectionCount() == 1, "moving the trigonum does not detect the joint again");

  // Back to the detected trigonum.
  plan->setUseLandmark(1, false);
  Expect(std::abs(Shown(plan, "FriedmanVersionLabel") - friedman) < 1e-9,
         "unticking Use restores the detected angles");

  // A bone without a glenoid.
  bm::Voxmap block({30, 30, 30}, 1.0, {0, 0, 0});
  for (int k = 5; k < 25; ++k)
    for (int j = 5; j < 25; ++j)
      for (int i = 5; i < 25; ++i)
        block.SetFill(block.Index(i, j, k), bm::Voxmap::kFull);
  bm::BoneFractionImage blockImage;
  blockImage.Update(block);
  filter->SetInputData(blockImage.GetOutput());
  plan->findChild<QPushButton*>("PlanButton")->click();
  const QString status = plan->findChild<QLabel*>("PlanStatusLabel")->text();
  Expect(status.contains("no glenoid found"), "a block: " + status.left(80));
  Expect(std::isnan(Shown(plan, "FriedmanVersionLabel")), "a block: no angles shown");
  std::printf("%d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
