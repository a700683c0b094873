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
#include "pqQVTKWidget.h"
#include "pqServer.h"
#include "pqView.h"
#include "QVTKOpenGLStereoWidget.h"
#include "QVTKOpenGLWindow.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkNew.h"
#include "vtkSMPVRepresentationProxy.h"
#include "vtkSMProperty.h"
#include "vtkSMTransferFunctionProxy.h"
#include "vtkPVArrayInformation.h"
#include "vtkPVDataInformation.h"
#include "vtkPVDataSetAttributesInformation.h"
#include "vtkSMParaViewPipelineControllerWithRendering.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMViewProxy.h"

#include <QCoreApplication>
#include <QMouseEvent>
#include <QSignalBlocker>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace {
/// A session's figures now as a plan step's entry of the plan's result (bmPlanResult.h): its
/// reached depth (mm), removed volume (mm^3), thrust (N) and torque (N mm) at its end, and its
/// time (s).
QString SessionFigures(vtkSMProxy* session, int step, const char* name, const char* tool) {
  session->UpdatePropertyInformation();
  QJsonObject summary;
  summary["reached_depth_mm"] = vtkSMPropertyHelper(session, "DepthInfo").GetAsDouble();
  summary["removed_volume_mm3"] = vtkSMPropertyHelper(session, "RemovedVolumeInfo").GetAsDouble();
  // The forces now, not a mean over the step (the report's mean reads "-").
  summary["thrust_at_end_N"] = vtkSMPropertyHelper(session, "ThrustInfo").GetAsDouble();
  summary["torque_at_end_Nmm"] = vtkSMPropertyHelper(session, "TorqueInfo").GetAsDouble();
  summary["time_s"] = vtkSMPropertyHelper(session, "TimeInfo").GetAsDouble();
  QJsonObject entry;
  entry["step"] = step;
  entry["name"] = name;
  entry["description"] = QString("run in the viewer as a session");
  entry["tool"] = tool;
  entry["summary"] = summary;
  return QString::fromUtf8(QJsonDocument(entry).toJson(QJsonDocument::Compact));
}

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
    this->PlanViewSet = false;
    // Handles dragged in the 3D view change the landmarks' properties (checked, or unchecked
    // until Apply): the section follows them.
    vtkSMProxy* p = this->GlenoidPlan->getProxy();
    this->PlanObserver = p->AddObserver(vtkCommand::PropertyModifiedEvent, this,
                                        &pqBMDockWindow::onPlanPropertyModified);
    for (const char* name : {"GlenoidCentre", "Trigonum", "InferiorAngle"})
      p->GetProperty(name)->AddObserver(vtkCommand::UncheckedPropertyModifiedEvent, this,
                                        &pqBMDockWindow::onPlanPropertyModified);
  }
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(this->GlenoidPlan->getProxy());
  struct Setting { // the properties set here are not handle drags
    bool& flag;
    explicit Setting(bool& f) : flag(f) { flag = true; }
    ~Setting() { flag = false; }
  } setting(this->SettingPlan);
  vtkSMPropertyHelper(proxy, "Input").Set(this->PlanInput->getProxy(), 0);
  // The glenoid placed by clicks in the 3D view: a point on the face, or rim points.
  vtkSMPropertyHelper(proxy, "UseFacePoint").Set(w->useFacePoint() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "FacePoint").Set(w->facePoint().constData(), 3);
  const QVector<double> rim = w->rimPoints();
  vtkSMPropertyHelper(proxy, "RimPoints").Set(rim.constData(), unsigned(rim.size()));
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
  r.implausible = vtkSMPropertyHelper(proxy, "ImplausibleInfo").GetAsInt() != 0;
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
  this->showPlanGlyphs();
  if (!this->PlanViewSet) { // the first plan: look at it as its pictures do
    this->PlanViewSet = true;
    this->viewPlan();
  }
}

void pqBMDockWindow::showPlanGlyphs() {
  pqView* view = pqActiveObjects::instance().activeView();
  if (!view || !this->GlenoidPlan)
    return;
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  vtkSMProxy* repr = controller->Show(vtkSMSourceProxy::SafeDownCast(this->GlenoidPlan->getProxy()),
                                      0, view->getViewProxy());
  if (repr) {
    // Each part in its own colour (bmPlanGlyphs.h): the RGB array drawn as it is.
    vtkSMPVRepresentationProxy::SetScalarColoring(repr, "Colors", vtkDataObject::POINT);
    vtkSMPropertyHelper(repr, "MapScalars", /*quiet=*/true).Set(0);
    vtkSMPVRepresentationProxy::SetScalarBarVisibility(repr, view->getViewProxy(), false);
    repr->UpdateVTKObjects();
  }
  view->render();
}

void pqBMDockWindow::onPlanPropertyModified(vtkObject*, unsigned long event, void* name) {
  if (this->SettingPlan)
    return;
  if (event == vtkCommand::PropertyModifiedEvent) {
    const std::string property = name ? static_cast<const char*>(name) : "";
    if (property != "GlenoidCentre" && property != "Trigonum" && property != "InferiorAngle")
      return;
  }
  this->HandleSync->start();
}

void pqBMDockWindow::syncDraggedLandmarks() {
  if (!this->GlenoidPlan || this->Starting)
    return;
  qBMPlanWidget* w = this->Panel->planWidget();
  vtkSMProxy* proxy = this->GlenoidPlan->getProxy();
  const char* names[3] = {"GlenoidCentre", "Trigonum", "InferiorAngle"};
  bool moved = false;
  {
    const QSignalBlocker block(w); // one plan below, not one per landmark
    for (int i = 0; i < 3; ++i) {
      vtkSMPropertyHelper helper(proxy, names[i]);
      helper.SetUseUnchecked(true); // a drag not yet applied
      QVector<double> p(3);
      helper.Get(p.data(), 3);
      // The section shows 0.01 mm: a point within half of that of the shown one did not move.
      const QVector<double> shown = w->landmark(i);
      if (std::max({std::abs(p[0] - shown[0]), std::abs(p[1] - shown[1]),
                    std::abs(p[2] - shown[2])}) > 0.0051) {
        w->setLandmark(i, p); // and uses it
        moved = true;
      }
    }
  }
  if (moved)
    this->planGlenoid();
}

void pqBMDockWindow::setPlacementMode(int mode) {
  for (const QPointer<QObject>& target : this->PlaceTargets)
    if (target)
      target->removeEventFilter(this);
  this->PlaceTargets.clear();
  if (this->PlaceView)
    this->PlaceView->unsetCursor();
  this->PlaceView = nullptr;
  this->PlacePressed = false;
  pqView* view = pqActiveObjects::instance().activeView();
  if (mode == 0 || !view || !view->widget())
    return;
  this->PlaceView = view->widget();
  this->PlaceView->setCursor(Qt::CrossCursor);
  // The mouse reaches the view's OpenGL window, embedded in the widget (QVTKOpenGLStereoWidget),
  // not the widget itself.
  this->PlaceTargets << this->PlaceView.data();
  if (auto* pqWidget = qobject_cast<pqQVTKWidget*>(view->widget())) {
    this->PlaceTargets << pqWidget->renderWidget();
    if (auto* stereo = qobject_cast<QVTKOpenGLStereoWidget*>(pqWidget->renderWidget()))
      this->PlaceTargets << static_cast<QObject*>(stereo->embeddedOpenGLWindow());
  }
  for (const QPointer<QObject>& target : this->PlaceTargets)
    if (target) {
      target->installEventFilter(this);
    }
}

bool pqBMDockWindow::placementEvent(QEvent* event) {
  qBMPlanWidget* w = this->Panel->planWidget();
  if (w->placementMode() == 0)
    return false;
  if (event->type() == QEvent::MouseButtonPress) {
    auto* e = static_cast<QMouseEvent*>(event);
    if (e->button() == Qt::LeftButton) {
      this->PlacePress = e->pos();
      this->PlacePressed = true;
    }
    return false; // a drag still turns the camera
  }
  if (event->type() != QEvent::MouseButtonRelease)
    return false;
  auto* e = static_cast<QMouseEvent*>(event);
  if (e->button() != Qt::LeftButton || !this->PlacePressed)
    return false;
  this->PlacePressed = false;
  if ((e->pos() - this->PlacePress).manhattanLength() > 4)
    return false; // a drag, not a click
  double p[3];
  if (this->pickPointAt(e->pos(), p))
    w->addPlacedPoint({p[0], p[1], p[2]});
  return false;
}

void pqBMDockWindow::viewPlan() {
  pqView* view = pqActiveObjects::instance().activeView();
  if (!view || !this->GlenoidPlan)
    return;
  vtkSMProxy* proxy = this->GlenoidPlan->getProxy();
  proxy->UpdatePropertyInformation();
  double c[10];
  vtkSMPropertyHelper(proxy, "PlanCameraInfo").Get(c, 10);
  if (!(c[9] > 0))
    return; // no plan
  // The view's 30 deg angle shows twice the pictures' half height at this distance: the glenoid
  // with the scapula's neck around it.
  const double distance = 2.0 * c[9] / std::tan(15.0 * 3.14159265358979323846 / 180.0);
  const double position[3] = {c[0] + distance * c[3], c[1] + distance * c[4],
                              c[2] + distance * c[5]};
  // The bone's surface again, not a slice through it.
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  if (this->PlanSlice)
    controller->Hide(vtkSMSourceProxy::SafeDownCast(this->PlanSlice->getProxy()), 0,
                     view->getViewProxy());
  if (this->CTSurface)
    controller->Show(vtkSMSourceProxy::SafeDownCast(this->CTSurface->getProxy()), 0,
                     view->getViewProxy());
  vtkSMProxy* v = view->getViewProxy();
  vtkSMPropertyHelper(v, "CameraFocalPoint").Set(c, 3);
  vtkSMPropertyHelper(v, "CameraPosition").Set(position, 3);
  vtkSMPropertyHelper(v, "CameraViewUp").Set(c + 6, 3);
  vtkSMPropertyHelper(v, "CameraParallelScale").Set(c[9]);
  v->UpdateVTKObjects();
  view->render();
}

void pqBMDockWindow::showPlanSlice(int kind) {
  qBMPlanWidget* w = this->Panel->planWidget();
  pqView* view = pqActiveObjects::instance().activeView();
  pqPipelineSource* image = this->CTImage ? this->CTImage.data() : this->PlanInput.data();
  if (!view || !this->GlenoidPlan || !image) {
    w->setReportStatus(tr("No slice: plan first."), false);
    return;
  }
  vtkSMProxy* proxy = this->GlenoidPlan->getProxy();
  proxy->UpdatePropertyInformation();
  const QVector<double> centre = Get3(proxy, "UsedGlenoidCentreInfo");
  const QVector<double> axis = Get3(proxy, "PlanAxisInfo");
  if (std::abs(axis[0]) + std::abs(axis[1]) + std::abs(axis[2]) == 0) {
    w->setReportStatus(tr("No slice: plan first."), false);
    return;
  }
  // Axial: seen from the feet, anterior up (LPS: -y). Along the axis: the plane holding the axis
  // and the superior direction, seen from its normal, superior up.
  double normal[3] = {0, 0, 1}, up[3] = {0, -1, 0}, toEye[3] = {0, 0, -1};
  if (kind == 1) {
    double n[3] = {axis[1], -axis[0], 0}; // axis x z
    const double len = std::hypot(n[0], n[1]);
    if (len < 1e-6)
      n[0] = 1, n[1] = 0; // an axis along z: any vertical plane
    else
      n[0] /= len, n[1] /= len;
    for (int a = 0; a < 3; ++a)
      normal[a] = toEye[a] = n[a];
    up[0] = 0, up[1] = 0, up[2] = 1;
  }
  pqObjectBuilder* builder = pqApplicationCore::instance()->getObjectBuilder();
  if (this->PlanSlice &&
      vtkSMPropertyHelper(this->PlanSlice->getProxy(), "Input").GetAsProxy() != image->getProxy()) {
    builder->destroy(this->PlanSlice);
    this->PlanSlice = nullptr;
  }
  if (!this->PlanSlice)
    this->PlanSlice = builder->createFilter("filters", "Cut", image);
  if (!this->PlanSlice) {
    w->setReportStatus(tr("Could not create a Slice filter."), false);
    return;
  }
  vtkSMProxy* slice = this->PlanSlice->getProxy();
  vtkSMProxy* plane = vtkSMPropertyHelper(slice, "CutFunction").GetAsProxy();
  if (plane) {
    vtkSMPropertyHelper(plane, "Origin").Set(centre.constData(), 3);
    vtkSMPropertyHelper(plane, "Normal").Set(normal, 3);
    plane->UpdateVTKObjects();
  }
  slice->UpdateVTKObjects();
  this->PlanSlice->updatePipeline();
  this->PlanSlice->setModifiedState(pqProxy::UNMODIFIED);
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  if (vtkSMProxy* repr =
          controller->Show(vtkSMSourceProxy::SafeDownCast(slice), 0, view->getViewProxy())) {
    // In grey, as a CT is read (coloured by its scalars, as Show chose).
    if (auto* lut = vtkSMTransferFunctionProxy::SafeDownCast(
            vtkSMPropertyHelper(repr, "LookupTable", true).GetAsProxy()))
      lut->ApplyPreset("Grayscale", true);
    repr->UpdateVTKObjects();
  }
  // The plan stays the active source: the slice's plane widget (a large red circle) is not
  // shown over the plan.
  pqActiveObjects::instance().setActiveSource(this->GlenoidPlan);
  // The bone's surface would hide the slice through it (View plan shows it again).
  if (this->CTSurface)
    controller->Hide(vtkSMSourceProxy::SafeDownCast(this->CTSurface->getProxy()), 0,
                     view->getViewProxy());
  // Square to the slice, about 80 mm across around the glenoid centre.
  const double distance = 150.0;
  const double position[3] = {centre[0] + distance * toEye[0], centre[1] + distance * toEye[1],
                              centre[2] + distance * toEye[2]};
  vtkSMProxy* v = view->getViewProxy();
  vtkSMPropertyHelper(v, "CameraFocalPoint").Set(centre.constData(), 3);
  vtkSMPropertyHelper(v, "CameraPosition").Set(position, 3);
  vtkSMPropertyHelper(v, "CameraViewUp").Set(up, 3);
  v->UpdateVTKObjects();
  view->render();
}

void pqBMDockWindow::writePlanReport() {
  qBMPlanWidget* w = this->Panel->planWidget();
  const QString folder = w->reportFolder().trimmed();
  if (!this->GlenoidPlan) {
    w->setReportStatus(tr("No report: plan first."), false);
    return;
  }
  if (folder.isEmpty()) {
    w->setReportStatus(tr("No report: choose a folder for it first."), false);
    return;
  }
  this->invokePlanWriter("WriteReport", tr("No report: %1"), [&](vtkSMProxy* proxy) {
    vtkSMPropertyHelper(proxy, "ReportDirectory").Set(folder.toUtf8().constData());
  });
}

void pqBMDockWindow::invokePlanWriter(const char* command, const QString& refusal,
                                      const std::function<void(vtkSMProxy*)>& set) {
  qBMPlanWidget* w = this->Panel->planWidget();
  vtkSMProxy* proxy = this->GlenoidPlan->getProxy();
  {
    const bool was = this->SettingPlan;
    this->SettingPlan = true;
    set(proxy);
    proxy->UpdateVTKObjects();
    this->SettingPlan = was;
  }
  proxy->InvokeCommand(command);
  proxy->UpdatePropertyInformation();
  const QString error =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "ReportErrorInfo").GetAsString());
  if (!error.isEmpty()) {
    w->setReportStatus(refusal.arg(error), false);
    return;
  }
  const QString files =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "ReportFilesInfo").GetAsString());
  const QString folder =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "ReportDirectory").GetAsString());
  w->setReportStatus(tr("Wrote %1 in %2.").arg(files.split('\n').join(", "), folder), true);
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
    // The plan's result compares the bone before the pin with the bone after the reaming: the
    // pin session's starting bone is saved now, with its figures, before it is replaced.
    this->PlanBeforeBone = dir.filePath("before-plan.nrrd");
    this->PinStepFigures = SessionFigures(this->Session->getProxy(), 1, "guide pin", "drill");
    vtkSMProxy* pin = this->Session->getProxy();
    vtkSMPropertyHelper(pin, "SaveInitialBone").Set(this->PlanBeforeBone.toUtf8().constData());
    pin->UpdateVTKObjects();
    vtkSMPropertyHelper(pin, "SaveInitialBone").Set("");
    pin->UpdateVTKObjects();
    if (!QFile::exists(this->PlanBeforeBone))
      this->PlanBeforeBone.clear(); // Write result says why
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
  if (this->PlanSlice) // the session's bone, not a slice through the CT, from now on
    if (pqView* view = pqActiveObjects::instance().activeView()) {
      vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
      controller->Hide(vtkSMSourceProxy::SafeDownCast(this->PlanSlice->getProxy()), 0,
                       view->getViewProxy());
    }
  this->KeepInitialBoneNext = step == 0; // the plan's result needs the bone before the pin
  this->StepSceneNext = true;
  this->startSession(path, 0, 0, session->deviceType());
  this->StepSceneNext = false;
  this->PinStepSession = step == 0 ? this->Session : nullptr;
  this->ReamStepSession = step == 1 ? this->Session : nullptr;
}

void pqBMDockWindow::writePlanResult() {
  qBMPlanWidget* w = this->Panel->planWidget();
  const QString folder = w->reportFolder().trimmed();
  if (!this->GlenoidPlan) {
    w->setReportStatus(tr("No result: plan first."), false);
    return;
  }
  if (folder.isEmpty()) {
    w->setReportStatus(tr("No result: choose a folder for it first."), false);
    return;
  }
  if (!this->ReamStepSession || this->ReamStepSession != this->Session ||
      this->PlanBeforeBone.isEmpty()) {
    w->setReportStatus(tr("No result: run this plan's guide pin, then its reaming (the result "
                          "compares the bone before the pin with the bone the reaming left)."),
                       false);
    return;
  }
  // The reaming session's bone now, and its figures.
  vtkSMProxy* ream = this->Session->getProxy();
  const QString after = QFileInfo(this->PlanBeforeBone).dir().filePath("after-ream.nrrd");
  vtkSMPropertyHelper(ream, "SaveBone").Set(after.toUtf8().constData());
  ream->UpdateVTKObjects();
  vtkSMPropertyHelper(ream, "SaveBone").Set("");
  ream->UpdateVTKObjects();
  ream->UpdatePropertyInformation();
  const QString saveError =
      QString::fromStdString(vtkSMPropertyHelper(ream, "LastErrorInfo").GetAsString());
  if (!saveError.isEmpty() || !QFile::exists(after)) {
    w->setReportStatus(tr("No result: the reamed bone could not be saved: %1").arg(saveError),
                       false);
    return;
  }
  const QString steps =
      QString("[%1,%2]").arg(this->PinStepFigures, SessionFigures(ream, 2, "ream", "reamer"));
  this->invokePlanWriter("WriteResult", tr("No result: %1"), [&](vtkSMProxy* proxy) {
    vtkSMPropertyHelper(proxy, "ReportDirectory").Set(folder.toUtf8().constData());
    vtkSMPropertyHelper(proxy, "ResultBeforeBone").Set(this->PlanBeforeBone.toUtf8().constData());
    vtkSMPropertyHelper(proxy, "ResultAfterBone").Set(after.toUtf8().constData());
    vtkSMPropertyHelper(proxy, "ResultSteps").Set(steps.toUtf8().constData());
    vtkSMPropertyHelper(proxy, "ResultAsDicom").Set(w->resultAsDicom() ? 1 : 0);
  });
}
