// pqBMDockPlanning.cxx - the dock's glue for the panel's Planning section (pqBMDockWindow.h:
// planGlenoid, runPlanStep): the section's settings onto a "BM Glenoid Plan" filter
// (vtkBMGlenoidPlanFilter), its results back into the section, and a plan's step run as a
// "BM Session" on the step's scene.
#include "pqBMDockWindow.h"

#include "qBMCTWidget.h"
#include "qBMPanel.h"
#include "qBMPlanWidget.h"
#include "qBMSessionWidget.h"

#include "pqActiveObjects.h"
#include "pqApplicationCore.h"
#include "pqObjectBuilder.h"
#include "pqOutputPort.h"
#include "pqPipelineSource.h"
#include "pqServer.h"
#include "pqView.h"
#include "vtkNew.h"
#include "vtkPVArrayInformation.h"
#include "vtkPVDataInformation.h"
#include "vtkPVDataSetAttributesInformation.h"
#include "vtkSMParaViewPipelineControllerWithRendering.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMViewProxy.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>

#include <string>

namespace {
QVector<double> Get3(vtkSMProxy* proxy, const char* name) {
  QVector<double> v(3);
  vtkSMPropertyHelper(proxy, name).Get(v.data(), 3);
  return v;
}
} // namespace

void pqBMDockWindow::planGlenoid() {
  if (this->Starting)
    return; // a session is being started
  pqServer* server = pqActiveObjects::instance().activeServer();
  qBMPlanWidget* w = this->Panel->planWidget();
  if (!server)
    return;
  // The bone: the selected image source (a voxmap opened, a BM CT Bone), else the one planned
  // on before, else the CT section's preview.
  pqPipelineSource* active = pqActiveObjects::instance().activeSource();
  if (active && active != this->GlenoidPlan && active != this->Session &&
      pqBMDockWindow::HoldsBoneFraction(active))
    this->PlanInput = active;
  if (!this->PlanInput)
    this->PlanInput = this->CTBone;
  if (!this->PlanInput) {
    w->setPlanFailure(tr("no bone image: preview the CT bone, or select a voxmap holding the "
                         "scapula and the humeral head (bmsim import --keep-all)"));
    return;
  }
  pqObjectBuilder* builder = pqApplicationCore::instance()->getObjectBuilder();
  if (!this->GlenoidPlan) {
    this->GlenoidPlan = builder->createFilter("sources", "BMGlenoidPlanFilter", this->PlanInput);
    if (!this->GlenoidPlan) {
      w->setPlanFailure(tr("could not create a BM Glenoid Plan filter"));
      return;
    }
  }
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(this->GlenoidPlan->getProxy());
  vtkSMPropertyHelper(proxy, "Input").Set(this->PlanInput->getProxy(), 0);
  const char* names[4] = {"GlenoidCentre", "Trigonum", "InferiorAngle", "FaceNormal"};
  for (int i = 0; i < 4; ++i) {
    vtkSMPropertyHelper(proxy, (std::string("Use") + names[i]).c_str())
        .Set(w->useLandmark(i) ? 1 : 0);
    vtkSMPropertyHelper(proxy, names[i]).Set(w->landmark(i).constData(), 3);
  }
  vtkSMPropertyHelper(proxy, "TargetVersion").Set(w->targetVersion());
  vtkSMPropertyHelper(proxy, "TargetInclination").Set(w->targetInclination());
  vtkSMPropertyHelper(proxy, "ReamDepth").Set(w->reamDepth());
  vtkSMPropertyHelper(proxy, "ReamerDiameter").Set(w->reamerDiameter());
  vtkSMPropertyHelper(proxy, "CTFileName")
      .Set(this->Panel->ctWidget()->ctFileName().toUtf8().constData());
  // Planned on the CT section's bone: the steps read the CT with its settings (raw values, HU
  // mapping, threshold, series, exclude points), not the defaults.
  std::string specification;
  if (this->CTBone && this->PlanInput == this->CTBone) {
    this->CTBone->getProxy()->UpdatePropertyInformation();
    specification =
        vtkSMPropertyHelper(this->CTBone->getProxy(), "BoneSpecificationInfo").GetAsString();
  }
  vtkSMPropertyHelper(proxy, "CTBoneSpecification").Set(specification.c_str());
  proxy->UpdateVTKObjects();
  this->GlenoidPlan->updatePipeline();
  this->GlenoidPlan->setModifiedState(pqProxy::UNMODIFIED);
  proxy->UpdatePropertyInformation();
  const QString error =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "LastErrorInfo").GetAsString());
  if (!error.isEmpty()) {
    w->setPlanFailure(error);
    return;
  }
  qBMPlanResult r;
  r.friedmanVersionDeg = vtkSMPropertyHelper(proxy, "FriedmanVersionInfo").GetAsDouble();
  r.version3DDeg = vtkSMPropertyHelper(proxy, "Version3DInfo").GetAsDouble();
  r.inclinationDeg = vtkSMPropertyHelper(proxy, "InclinationInfo").GetAsDouble();
  r.heightMm = vtkSMPropertyHelper(proxy, "GlenoidHeightInfo").GetAsDouble();
  r.widthMm = vtkSMPropertyHelper(proxy, "GlenoidWidthInfo").GetAsDouble();
  r.faceRadiusMm = vtkSMPropertyHelper(proxy, "FaceRadiusInfo").GetAsDouble();
  r.correctionDeg = vtkSMPropertyHelper(proxy, "CorrectionInfo").GetAsDouble();
  r.reamerFits = vtkSMPropertyHelper(proxy, "ReamerFitsInfo").GetAsInt() != 0;
  r.glenoidCentre = Get3(proxy, "UsedGlenoidCentreInfo");
  r.trigonum = Get3(proxy, "UsedTrigonumInfo");
  r.inferiorAngle = Get3(proxy, "UsedInferiorAngleInfo");
  r.faceNormal = Get3(proxy, "UsedFaceNormalInfo");
  r.entry = Get3(proxy, "PlanEntryInfo");
  r.axis = Get3(proxy, "PlanAxisInfo");
  const QString warnings =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "WarningsInfo").GetAsString());
  if (!warnings.isEmpty())
    r.warnings = warnings.split('\n');
  r.canRunSteps = !std::string(vtkSMPropertyHelper(proxy, "PlanSceneInfo").GetAsString()).empty();
  w->setPlanResult(r);
  // The landmarks not given take the used (detected) points, so that their handles in the 3D
  // view start there; with Use off they do not change the plan.
  const QVector<double>* used[4] = {&r.glenoidCentre, &r.trigonum, &r.inferiorAngle, &r.faceNormal};
  for (int i = 0; i < 4; ++i)
    if (!w->useLandmark(i))
      vtkSMPropertyHelper(proxy, names[i]).Set(used[i]->constData(), 3);
  proxy->UpdateVTKObjects();
  this->GlenoidPlan->setModifiedState(pqProxy::UNMODIFIED);
  if (pqView* view = pqActiveObjects::instance().activeView()) {
    vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
    controller->Show(proxy, 0, view->getViewProxy());
    view->render();
  }
}

void pqBMDockWindow::runPlanStep(int step) {
  if (this->Starting)
    return;
  qBMPlanWidget* w = this->Panel->planWidget();
  qBMSessionWidget* session = this->Panel->sessionWidget();
  if (!this->GlenoidPlan || (step != 0 && step != 1))
    return;
  vtkSMProxy* proxy = this->GlenoidPlan->getProxy();
  proxy->UpdatePropertyInformation();
  const std::string scene =
      vtkSMPropertyHelper(proxy, step == 0 ? "PinStepSceneInfo" : "ReamStepSceneInfo")
          .GetAsString();
  if (scene.empty()) {
    w->setPlanFailure(tr("no plan scene: name the CT in the CT section and plan again"));
    return;
  }
  const QDir dir(
      QDir::temp().filePath(QString("bm-plan-%1").arg(QCoreApplication::applicationPid())));
  dir.mkpath(".");
  const QString path = dir.filePath(step == 0 ? "step1-guide-pin.json" : "step2-ream.json");
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate) ||
      file.write(scene.c_str(), qint64(scene.size())) != qint64(scene.size())) {
    session->setSessionStatus(tr("Cannot write the step's scene %1").arg(path), false);
    return;
  }
  file.close();
  // The reaming runs on the bone this plan's guide-pin step left, and on no other: another
  // session's bone (the built-in phantom, another CT) would be reamed at this plan's place.
  if (step == 1 && (!this->Session || this->Session != this->PinStepSession)) {
    session->setSessionStatus(tr("Cannot run the reaming: run this plan's guide pin first (the "
                                 "reaming cuts the bone the guide-pin step leaves)."),
                              false);
    return;
  }
  // The step's own tool and bone: not the tool section's, not the CT section's bone.
  session->setUseChosenTool(false);
  this->Panel->ctWidget()->setUseCTBone(false);
  if (step == 1) {
    // Ream the bone the guide-pin step left.
    const QString bone = dir.filePath("after-guide-pin.nrrd");
    this->SavedBone.clear();
    this->saveBone(bone);
    if (this->SavedBone != bone) { // saveBone said why in the session's status
      session->setSessionStatus(tr("Cannot run the reaming: the guide-pin step's bone could not "
                                   "be saved to %1.")
                                    .arg(bone),
                                false);
      return;
    }
    session->setBoneFile(bone);
    session->setStartFromBoneFile(true);
  } else {
    session->setStartFromBoneFile(false);
  }
  this->startSession(path, 0, 0, session->deviceType());
  this->PinStepSession = step == 0 ? this->Session : nullptr;
}
