// pqBMDockWindow.cxx - see pqBMDockWindow.h.
#include "pqBMDockWindow.h"

#include "bmPanelLogic.h"
#include "qBMCTWidget.h"
#include "qBMChartsWidget.h"
#include "qBMPanel.h"
#include "qBMPlanWidget.h"
#include "qBMSessionWidget.h"
#include "qBMToolWidget.h"
#include "vtkBMSessionSource.h"

#include "pqActiveObjects.h"
#include "pqApplicationCore.h"
#include "pqEventDispatcher.h"
#include "pqObjectBuilder.h"
#include "pqOutputPort.h"
#include "pqPipelineSource.h"
#include "pqServer.h"
#include "pqUndoStack.h"
#include "pqView.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkPVArrayInformation.h"
#include "vtkPVDataInformation.h"
#include "vtkPVDataSetAttributesInformation.h"
#include "vtkNew.h"
#include "vtkSMParaViewPipelineControllerWithRendering.h"
#include "vtkSMPVRepresentationProxy.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMRenderViewProxy.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMViewProxy.h"

#include <QApplication>
#include <QEventLoop>
#include <QCursor>
#include <QShortcut>
#include <QWheelEvent>
#include <QScrollArea>
#include <QTimer>

#include <string>

pqBMDockWindow::pqBMDockWindow(QWidget* parent)
    : Superclass(tr("Bone Machining"), parent), Panel(new qBMPanel), Poll(new QTimer(this)) {
  // Object names make the widgets addressable by ParaView's XML GUI tests (Testing/GUI).
  auto* scroll = new QScrollArea(this);
  scroll->setObjectName("ScrollArea");
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setWidget(this->Panel);
  this->setWidget(scroll);
  qBMSessionWidget* session = this->Panel->sessionWidget();
  QObject::connect(this->Panel->toolWidget(), &qBMToolWidget::addToolRequested, this,
                   &pqBMDockWindow::addTool);
  QObject::connect(session, &qBMSessionWidget::startSessionRequested, this,
                   &pqBMDockWindow::startSession);
  QObject::connect(session, &qBMSessionWidget::pauseSessionRequested, this,
                   &pqBMDockWindow::pauseSession);
  QObject::connect(session, &qBMSessionWidget::stopSessionRequested, this,
                   &pqBMDockWindow::stopSession);
  QObject::connect(session, &qBMSessionWidget::toolDepthChanged, this,
                   &pqBMDockWindow::setToolDepth);
  QObject::connect(session, &qBMSessionWidget::saveBoneRequested, this, &pqBMDockWindow::saveBone);
  QObject::connect(session, &qBMSessionWidget::volumeRenderingToggled, this,
                   &pqBMDockWindow::setVolumeRendering);
  QObject::connect(this->Panel->ctWidget(), &qBMCTWidget::previewCTRequested, this,
                   &pqBMDockWindow::previewCT);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::planRequested, this,
                   &pqBMDockWindow::planGlenoid);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::runStepRequested, this,
                   &pqBMDockWindow::runPlanStep);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::placementModeChanged, this,
                   &pqBMDockWindow::setPlacementMode);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::viewPlanRequested, this,
                   &pqBMDockWindow::viewPlan);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::sliceRequested, this,
                   &pqBMDockWindow::showPlanSlice);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::writeReportRequested, this,
                   &pqBMDockWindow::writePlanReport);
  QObject::connect(this->Panel->planWidget(), &qBMPlanWidget::writeResultRequested, this,
                   &pqBMDockWindow::writePlanResult);
  this->HandleSync = new QTimer(this);
  this->HandleSync->setSingleShot(true);
  this->HandleSync->setInterval(250); // a drag's last move, not each one, is planned
  QObject::connect(this->HandleSync, &QTimer::timeout, this, &pqBMDockWindow::syncDraggedLandmarks);
  // Picking in the 3D view (the surface point under the mouse): Ctrl+Shift+E adds an exclude
  // point, Ctrl+Shift+I sets the include seed of the CT bone.
  auto* exclude = new QShortcut(QKeySequence(tr("Ctrl+Shift+E")), this);
  auto* seed = new QShortcut(QKeySequence(tr("Ctrl+Shift+I")), this);
  exclude->setContext(Qt::ApplicationShortcut); // the mouse is over the view, not the dock
  seed->setContext(Qt::ApplicationShortcut);
  QObject::connect(exclude, &QShortcut::activated, this, [this]() {
    double p[3];
    if (this->pickPoint(p))
      this->Panel->ctWidget()->addExcludePoint(p[0], p[1], p[2]);
  });
  QObject::connect(seed, &QShortcut::activated, this, [this]() {
    double p[3];
    if (this->pickPoint(p))
      this->Panel->ctWidget()->setSeed({p[0], p[1], p[2]});
  });
  this->Poll->setInterval(33);
  QObject::connect(this->Poll, &QTimer::timeout, this, &pqBMDockWindow::pollSession);
}

pqBMDockWindow::~pqBMDockWindow() {
  if (this->GlenoidPlan && this->PlanObserver)
    this->GlenoidPlan->getProxy()->RemoveObserver(this->PlanObserver);
}

bool pqBMDockWindow::HoldsImage(pqPipelineSource* source) {
  if (!source || source->getNumberOfOutputPorts() < 1)
    return false;
  vtkPVDataInformation* info = source->getOutputPort(0)->getDataInformation();
  return info && info->GetDataSetType() == VTK_IMAGE_DATA;
}

bool pqBMDockWindow::HoldsBoneFraction(pqPipelineSource* source) {
  if (!HoldsImage(source))
    return false;
  vtkPVDataSetAttributesInformation* points =
      source->getOutputPort(0)->getDataInformation()->GetPointDataInformation();
  if (points->GetArrayInformation("BoneFraction"))
    return true;
  // A voxmap file opened by ParaView's reader: its one array holds fill fractions in [0, 1]
  // (bmVoxmapFile.h), where a CT holds HU or a display window's 0-255.
  vtkPVArrayInformation* scalars = points->GetAttributeInformation(vtkDataSetAttributes::SCALARS);
  if (!scalars && points->GetNumberOfArrays() > 0)
    scalars = points->GetArrayInformation(0);
  if (!scalars || scalars->GetNumberOfComponents() != 1)
    return false;
  const double* range = scalars->GetComponentRange(0);
  return range[0] >= 0.0 && range[1] <= 1.0 && range[1] > 0.0;
}

namespace {
/// The bone's and the tool's colours in the view (RGB 0..1): bone ivory, tool steel blue.
const double kBoneColour[3] = {0.93, 0.87, 0.74};
const double kToolColour[3] = {0.35, 0.5, 0.8};

/// Shows `port` of `proxy` in `view` in a solid colour (no scalar colouring).
vtkSMProxy* ShowInColour(vtkSMSourceProxy* proxy, int port, pqView* view, const double rgb[3]) {
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  vtkSMProxy* repr = controller->Show(proxy, port, view->getViewProxy());
  if (repr) {
    vtkSMPVRepresentationProxy::SetScalarColoring(repr, nullptr, vtkDataObject::POINT);
    vtkSMPropertyHelper(repr, "DiffuseColor").Set(rgb, 3);
    vtkSMPropertyHelper(repr, "AmbientColor").Set(rgb, 3);
    repr->UpdateVTKObjects();
  }
  return repr;
}

/// Points the view's camera at what `port` of `proxy` holds (its data bounds, as ParaView's Reset
/// Camera does for the whole scene) and renders. A representation's own bounds are not known
/// until the view has rendered it once, so vtkSMRenderViewProxy::ZoomTo on a new representation
/// left the camera where it was, often looking at nothing.
void FrameBounds(pqView* view, const double b[6]) {
  auto* renderView = vtkSMRenderViewProxy::SafeDownCast(view->getViewProxy());
  if (renderView && b[0] < b[1] && b[2] < b[3] && b[4] < b[5])
    renderView->ResetCamera(const_cast<double*>(b));
  else
    view->resetDisplay();
  view->render();
}

void FrameOutput(pqView* view, vtkSMSourceProxy* proxy, int port) {
  double b[6] = {1, 0, 1, 0, 1, 0};
  if (vtkPVDataInformation* info = proxy->GetDataInformation(port))
    info->GetBounds(b);
  FrameBounds(view, b);
}
} // namespace

bool pqBMDockWindow::eventFilter(QObject* watched, QEvent* event) {
  // The wheel over the 3D view moves the mouse proxy's depth while a mouse-proxy session runs.
  if (watched == this->WheelView && event->type() == QEvent::Wheel && this->Session &&
      this->Poll->isActive()) {
    const int delta = static_cast<QWheelEvent*>(event)->angleDelta().y();
    if (delta != 0)
      this->Panel->sessionWidget()->stepToolDepth(delta > 0 ? 1 : -1);
    return true;
  }
  if (this->PlaceView && this->PlaceTargets.contains(watched) && this->placementEvent(event))
    return true;
  return Superclass::eventFilter(watched, event);
}

bool pqBMDockWindow::pickPoint(double world[3]) const {
  pqView* view = pqActiveObjects::instance().activeView();
  auto* renderView = view ? vtkSMRenderViewProxy::SafeDownCast(view->getViewProxy()) : nullptr;
  QWidget* widget = view ? view->widget() : nullptr;
  if (!renderView || !widget)
    return false;
  return this->pickPointAt(widget->mapFromGlobal(QCursor::pos()), world);
}

bool pqBMDockWindow::pickPointAt(const QPoint& local, double world[3]) const {
  pqView* view = pqActiveObjects::instance().activeView();
  auto* renderView = view ? vtkSMRenderViewProxy::SafeDownCast(view->getViewProxy()) : nullptr;
  QWidget* widget = view ? view->widget() : nullptr;
  if (!renderView || !widget)
    return false;
  if (!widget->rect().contains(local))
    return false; // the mouse is not over the view
  // Display coordinates: pixels from the bottom left.
  const double ratio = widget->devicePixelRatioF();
  const int display[2] = {int(local.x() * ratio), int((widget->height() - 1 - local.y()) * ratio)};
  double normal[3];
  return renderView->ConvertDisplayToPointOnSurface(display, world, normal);
}

void pqBMDockWindow::addTool(int toolType, int resolution) {
  pqServer* server = pqActiveObjects::instance().activeServer();
  qBMToolWidget* tool = this->Panel->toolWidget();
  if (!server)
    return;
  BEGIN_UNDO_SET(tr("Create BM Tool"));
  pqPipelineSource* source = pqApplicationCore::instance()->getObjectBuilder()->createSource(
      "sources", "BMToolSource", server);
  if (source) {
    vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(source->getProxy());
    vtkSMPropertyHelper(proxy, "ToolType").Set(toolType);
    vtkSMPropertyHelper(proxy, "Resolution").Set(resolution);
    // The panel's edited parameters (its whole, validated specification; "type" is ignored).
    vtkSMPropertyHelper(proxy, "Parameters").Set(tool->toolSpecification().toUtf8().constData());
    proxy->UpdateVTKObjects();
    source->updatePipeline();
    source->setModifiedState(pqProxy::UNMODIFIED);
    if (pqView* view = pqActiveObjects::instance().activeView()) {
      ShowInColour(proxy, 0, view, kToolColour);
      view->resetDisplay();
      view->render();
    }
    pqActiveObjects::instance().setActiveSource(source);
    tool->setStatusMessage(tr("Added %1 to the pipeline.").arg(source->getSMName()));
  } else {
    tool->setStatusMessage(tr("Could not create a BM Tool source: is the plugin loaded "
                              "on the server?"));
  }
  END_UNDO_SET();
}

void pqBMDockWindow::removeSession() {
  this->Poll->stop();
  if (this->WheelView)
    this->WheelView->removeEventFilter(this);
  this->WheelView = nullptr;
  if (!this->Session)
    return;
  this->Session->getProxy()->InvokeCommand("Stop");
  pqApplicationCore::instance()->getObjectBuilder()->destroy(this->Session);
  this->Session = nullptr;
}

void pqBMDockWindow::startSession(const QString& scene, int voxmapResolution, int shellResolution,
                                  int deviceType) {
  if (this->Starting)
    return; // one start at a time (Start is disabled meanwhile)
  pqServer* server = pqActiveObjects::instance().activeServer();
  qBMSessionWidget* panel = this->Panel->sessionWidget();
  qBMToolWidget* tool = this->Panel->toolWidget();
  qBMCTWidget* ct = this->Panel->ctWidget();
  if (!server)
    return;
  if (panel->useChosenTool() && !tool->isToolValid()) {
    // Refused before any source is made: the scene's tool must not stand in silently.
    panel->setSessionStatus(tr("Cannot start: %1").arg(tool->toolSummary()), false);
    return;
  }
  std::string boneCT;
  // A saved bone replaces the CT's (it is that bone, cut): the CT bone is not imported again.
  const bool fromFile = panel->startFromBoneFile();
  if (ct->useCTBone() && !fromFile) {
    this->previewCT(); // the CT settings as they are now, checked before the session starts
    if (!this->CTBone) {
      panel->setSessionStatus(tr("Cannot start: no BM CT Bone source."), false);
      return;
    }
    vtkSMProxy* ctProxy = this->CTBone->getProxy();
    const std::string error = vtkSMPropertyHelper(ctProxy, "LastErrorInfo").GetAsString();
    if (!error.empty()) {
      panel->setSessionStatus(
          tr("Cannot start on the CT bone: %1").arg(QString::fromStdString(error)), false);
      return;
    }
    boneCT = vtkSMPropertyHelper(ctProxy, "BoneSpecificationInfo").GetAsString();
  }
  // The new session replaces the previous one, its bone and tool in the view too.
  this->removeSession();
  this->Panel->chartsWidget()->clearHistory();
  pqPipelineSource* source = pqApplicationCore::instance()->getObjectBuilder()->createSource(
      "sources", "BMSessionSource", server);
  if (!source) {
    panel->setSessionStatus(tr("Could not create a BM Session source."), false);
    return;
  }
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(source->getProxy());
  vtkSMPropertyHelper(proxy, "Scene").Set(scene.toUtf8().constData());
  vtkSMPropertyHelper(proxy, "VoxmapResolution").Set(voxmapResolution);
  vtkSMPropertyHelper(proxy, "ShellResolution").Set(shellResolution);
  vtkSMPropertyHelper(proxy, "DeviceType").Set(deviceType);
  vtkSMPropertyHelper(proxy, "ToolDepth").Set(panel->toolDepth());
  vtkSMPropertyHelper(proxy, "Method").Set(panel->method());
  vtkSMPropertyHelper(proxy, "Tool")
      .Set(panel->useChosenTool() ? tool->toolSpecification().toUtf8().constData() : "");
  vtkSMPropertyHelper(proxy, "BoneFile")
      .Set(panel->startFromBoneFile() ? panel->boneFile().toUtf8().constData() : "");
  vtkSMPropertyHelper(proxy, "VolumeOutput").Set(panel->volumeRendering() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "BoneCT").Set(boneCT.c_str());
  // The trial: a plan step's scene carries its own; a saved bone goes on where it was cut (the
  // trial saved in the file, BoneFileTrial); the CT bone takes the CT section's entry and axis;
  // else the scene's.
  const bool stepScene = this->StepSceneNext;
  vtkSMPropertyHelper(proxy, "BoneFileTrial").Set(stepScene ? 0 : 1);
  vtkSMPropertyHelper(proxy, "OverrideTrial")
      .Set(!stepScene && !fromFile && ct->useCTBone() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "Entry").Set(ct->entry().constData(), 3);
  vtkSMPropertyHelper(proxy, "Axis").Set(ct->axis().constData(), 3);
  // The panel's force scale is a Touch's (0, "per tool": the tool's); other devices keep theirs.
  vtkSMPropertyHelper(proxy, "ForceScale")
      .Set(deviceType == vtkBMSessionSource::TOUCH ? panel->forceScale() : 0.0);
  // Building the bone takes seconds (a glenoid's import): on the source's worker thread, while
  // the GUI goes on (the view redraws, the progress shows, Stop cancels).
  vtkSMPropertyHelper(proxy, "KeepInitialBone").Set(this->KeepInitialBoneNext ? 1 : 0);
  this->KeepInitialBoneNext = false;
  vtkSMPropertyHelper(proxy, "StartInBackground").Set(1);
  proxy->UpdateVTKObjects();
  panel->setBusy(true, tr("Building %1's bone and tool...").arg(source->getSMName()));
  this->Starting = source;
  proxy->InvokeCommand("Start");
  proxy->UpdatePropertyInformation();
  if (vtkSMPropertyHelper(proxy, "StartingInfo").GetAsInt() != 0) {
    // A played GUI test (ParaView's XML tests) must not go on to its next event while the
    // session starts: QtTesting plays events in any nested loop unless told to defer them, as
    // ParaView's own long waits do (pqLiveInsituManager).
    pqEventDispatcher::deferEventsIfBlocked(true);
    QEventLoop building;
    QTimer tick;
    tick.setInterval(30);
    QObject::connect(&tick, &QTimer::timeout, &building, [&]() {
      proxy->UpdatePropertyInformation();
      if (vtkSMPropertyHelper(proxy, "StartingInfo").GetAsInt() == 0)
        building.quit();
      else
        panel->setBusyProgress(
            vtkSMPropertyHelper(proxy, "StartProgressInfo").GetAsDouble(),
            QString::fromStdString(vtkSMPropertyHelper(proxy, "StartStageInfo").GetAsString()));
    });
    tick.start();
    building.exec();
    pqEventDispatcher::deferEventsIfBlocked(false);
  }
  this->Starting = nullptr;
  proxy->InvokeCommand("FinishStart");
  proxy->UpdatePropertyInformation();
  panel->setBusy(false);
  const std::string error = vtkSMPropertyHelper(proxy, "LastErrorInfo").GetAsString();
  if (!error.empty()) { // Start() failed (bad scene, import error) or was cancelled
    const QString name = source->getSMName();
    pqApplicationCore::instance()->getObjectBuilder()->destroy(source); // no pile of failures
    panel->setSessionStatus(
        error == "cancelled"
            ? tr("Start of %1 cancelled.").arg(name)
            : tr("Could not start %1: %2").arg(name, QString::fromStdString(error)),
        false);
    return;
  }
  source->updatePipeline();
  source->setModifiedState(pqProxy::UNMODIFIED);
  this->Session = source;
  if (pqView* view = pqActiveObjects::instance().activeView()) {
    ShowInColour(proxy, 0, view, kBoneColour);
    ShowInColour(proxy, 1, view, kToolColour);
    if (panel->volumeRendering())
      this->setVolumeRendering(true);
    // The camera frames the bone (the tool may start far above it): the voxmap's bounds, known
    // before the live surface's first extraction (which may take a few refreshes).
    double bounds[6];
    proxy->UpdatePropertyInformation();
    vtkSMPropertyHelper(proxy, "BoneBoundsInfo").Get(bounds, 6);
    FrameBounds(view, bounds);
    if (deviceType == vtkBMSessionSource::MOUSE && view->widget()) {
      this->WheelView = view->widget();
      this->WheelView->installEventFilter(this);
    }
  }
  this->ChartedFrame = -1;
  this->ChartClock.start();
  this->Poll->start();
  // Where the trial came from, when a saved bone was started (a plan step's scene has its own).
  const std::string trialSource =
      vtkSMPropertyHelper(proxy, "SessionTrialSourceInfo").GetAsString();
  QString started = tr("Started %1.").arg(source->getSMName());
  if (fromFile && !stepScene)
    started = trialSource == "the bone file's"
                  ? tr("Started %1 on the saved bone, where it was cut.").arg(source->getSMName())
                  : tr("Started %1 on the saved bone, at the scene's entry and axis (none was "
                       "saved with it).")
                        .arg(source->getSMName());
  const std::string startNote = vtkSMPropertyHelper(proxy, "SessionStartNoteInfo").GetAsString();
  if (!startNote.empty())
    started += " " + tr("Note: %1.").arg(QString::fromStdString(startNote));
  panel->setSessionStatus(started, true);
}

void pqBMDockWindow::pauseSession(bool paused) {
  if (!this->Session)
    return;
  this->Session->getProxy()->InvokeCommand(paused ? "Pause" : "Resume");
  this->Panel->sessionWidget()->setSessionStatus(
      (paused ? tr("Paused %1.") : tr("Resumed %1.")).arg(this->Session->getSMName()), true);
}

void pqBMDockWindow::stopSession() {
  if (this->Starting) { // cancels the start under way; startSession says so
    this->Starting->getProxy()->InvokeCommand("Stop");
    return;
  }
  this->Poll->stop();
  if (!this->Session)
    return;
  this->Session->getProxy()->InvokeCommand("Stop");
  this->Session->updatePipeline(); // the final cut, numbers and state
  this->ForceCharts = true;
  this->pollSession();
  this->ForceCharts = false;
  this->Panel->sessionWidget()->setSessionStatus(tr("Stopped %1.").arg(this->Session->getSMName()),
                                                 false);
}

void pqBMDockWindow::setToolDepth(double depthMm) {
  if (!this->Session)
    return;
  vtkSMProxy* proxy = this->Session->getProxy();
  vtkSMPropertyHelper(proxy, "ToolDepth").Set(depthMm);
  proxy->UpdateVTKObjects();
}

void pqBMDockWindow::saveBone(const QString& path) {
  qBMSessionWidget* panel = this->Panel->sessionWidget();
  if (!this->Session) {
    panel->setSessionStatus(tr("No session bone to save: start a session first."), false);
    return;
  }
  if (path.isEmpty()) {
    panel->setSessionStatus(tr("Choose a bone file (.nrrd or .mha) to save to."),
                            this->Poll->isActive());
    return;
  }
  vtkSMProxy* proxy = this->Session->getProxy();
  vtkSMPropertyHelper(proxy, "SaveBone").Set(path.toUtf8().constData());
  proxy->UpdateVTKObjects(); // SaveBone(path) runs here
  proxy->UpdatePropertyInformation();
  const std::string error = vtkSMPropertyHelper(proxy, "LastErrorInfo").GetAsString();
  vtkSMPropertyHelper(proxy, "SaveBone").Set(""); // so that the same path can be saved again
  proxy->UpdateVTKObjects();
  if (error.empty())
    this->SavedBone = path;
  panel->setSessionStatus(
      error.empty() ? tr("Saved the bone of %1 to %2.").arg(this->Session->getSMName(), path)
                    : tr("Could not save the bone: %1").arg(QString::fromStdString(error)),
      this->Poll->isActive());
}

void pqBMDockWindow::setVolumeRendering(bool on) {
  if (!this->Session)
    return; // the next session starts with the panel's choice
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(this->Session->getProxy());
  vtkSMPropertyHelper(proxy, "VolumeOutput").Set(on ? 1 : 0);
  proxy->UpdateVTKObjects();
  pqView* view = pqActiveObjects::instance().activeView();
  if (!view)
    return;
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  if (on) {
    this->Session->updatePipeline();
    vtkSMProxy* repr = controller->Show(proxy, 3, view->getViewProxy());
    if (repr) {
      vtkSMPVRepresentationProxy::SetScalarColoring(repr, "BoneFraction", vtkDataObject::POINT);
      vtkSMPropertyHelper(repr, "Representation").Set("Volume");
      repr->UpdateVTKObjects();
    }
    controller->Hide(proxy, 0, view->getViewProxy()); // the opaque surface would hide it
  } else {
    controller->Hide(proxy, 3, view->getViewProxy());
    ShowInColour(proxy, 0, view, kBoneColour);
  }
  view->render();
}

void pqBMDockWindow::previewCT() {
  if (this->Starting)
    return; // the session's bone is being built from these settings
  pqServer* server = pqActiveObjects::instance().activeServer();
  qBMCTWidget* ct = this->Panel->ctWidget();
  if (!server)
    return;
  QVector<double> exclude;
  QString excludeError;
  if (!ct->excludePoints(exclude, excludeError)) {
    ct->setCTPreview(0, 0, {}, {}, tr("exclude points: %1").arg(excludeError));
    return;
  }
  pqObjectBuilder* builder = pqApplicationCore::instance()->getObjectBuilder();
  // The CT: the file named in the section, else an image open in the pipeline (a reader's
  // output selected, or the one used before), never one of the dock's own outputs.
  pqPipelineSource* active = pqActiveObjects::instance().activeSource();
  if (ct->ctFileName().isEmpty() && active && active != this->CTBone && active != this->CTSurface &&
      active != this->Session && active != this->GlenoidPlan && HoldsImage(active) &&
      !HoldsBoneFraction(active))
    this->CTImage = active;
  if (!ct->ctFileName().isEmpty())
    this->CTImage = nullptr;
  if (!this->CTBone) {
    this->CTBone = builder->createSource("sources", "BMCTBoneSource", server);
    if (!this->CTBone) {
      ct->setCTPreview(0, 0, {}, {}, tr("could not create a BM CT Bone source"));
      return;
    }
  }
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(this->CTBone->getProxy());
  if (this->CTImage)
    vtkSMPropertyHelper(proxy, "Input").Set(this->CTImage->getProxy(), 0);
  else
    vtkSMPropertyHelper(proxy, "Input").RemoveAllValues();
  vtkSMPropertyHelper(proxy, "FileName").Set(ct->ctFileName().toUtf8().constData());
  vtkSMPropertyHelper(proxy, "IntensityMode").Set(ct->intensityMode());
  if (ct->intensityMode() == 1)
    vtkSMPropertyHelper(proxy, "RawThreshold").Set(ct->thresholdHU()); // the file's units
  else
    vtkSMPropertyHelper(proxy, "ThresholdHU").Set(ct->thresholdHU());
  vtkSMPropertyHelper(proxy, "HUMapping").Set(ct->huMapping().constData(), 2);
  vtkSMPropertyHelper(proxy, "ROI").Set(ct->roi().constData(), 6);
  vtkSMPropertyHelper(proxy, "Resolution").Set(ct->ctResolution());
  vtkSMPropertyHelper(proxy, "Axis").Set(ct->axis().constData(), 3);
  vtkSMPropertyHelper(proxy, "UseSeed").Set(ct->useSeed() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "Seed").Set(ct->seed().constData(), 3);
  vtkSMPropertyHelper(proxy, "KeepAllBones").Set(ct->keepAllBones() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "ExcludePoints").Set(exclude.constData(), exclude.size());
  vtkSMPropertyHelper(proxy, "UseBox").Set(ct->useBox() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "BoxCentre").Set(ct->boxCentre().constData(), 3);
  vtkSMPropertyHelper(proxy, "BoxHalfSizes").Set(ct->boxHalfSizes().constData(), 3);
  vtkSMPropertyHelper(proxy, "BoxRotation").Set(ct->boxRotation().constData(), 3);
  proxy->UpdateVTKObjects();
  this->CTBone->updatePipeline();
  this->CTBone->setModifiedState(pqProxy::UNMODIFIED);
  proxy->UpdatePropertyInformation();
  const QString error =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "LastErrorInfo").GetAsString());
  QVector<double> bounds(6), entry(3);
  vtkSMPropertyHelper(proxy, "BoneBoundsInfo").Get(bounds.data(), 6);
  vtkSMPropertyHelper(proxy, "SuggestedEntryInfo").Get(entry.data(), 3);
  ct->setCTPreview(vtkSMPropertyHelper(proxy, "BoneVoxelsInfo").GetAsIdType(),
                   vtkSMPropertyHelper(proxy, "BoneVolumeInfo").GetAsDouble(), bounds, entry,
                   error);
  pqView* view = pqActiveObjects::instance().activeView();
  if (!view || !error.isEmpty())
    return;
  // The bone as a surface: the bone fraction's 0.5 contour, made once and kept (a new preview
  // updates it; its display stays as the user left it).
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  const bool firstSurface = !this->CTSurface;
  if (!this->CTSurface) {
    this->CTSurface = builder->createFilter("filters", "Contour", this->CTBone);
    if (vtkSMProxy* c = this->CTSurface ? this->CTSurface->getProxy() : nullptr) {
      vtkSMPropertyHelper(c, "SelectInputScalars")
          .SetInputArrayToProcess(vtkDataObject::POINT, "BoneFraction");
      vtkSMPropertyHelper(c, "ContourValues").Set(0.5);
      c->UpdateVTKObjects();
    }
  }
  if (this->CTSurface) {
    this->CTSurface->updatePipeline();
    this->CTSurface->setModifiedState(pqProxy::UNMODIFIED);
    controller->Hide(proxy, 0, view->getViewProxy()); // the image itself: hidden by the surface
    if (firstSurface)
      ShowInColour(vtkSMSourceProxy::SafeDownCast(this->CTSurface->getProxy()), 0, view,
                   kBoneColour);
    else
      controller->Show(vtkSMSourceProxy::SafeDownCast(this->CTSurface->getProxy()), 0,
                       view->getViewProxy());
    FrameOutput(view, vtkSMSourceProxy::SafeDownCast(this->CTSurface->getProxy()), 0);
  } else if (vtkSMProxy* repr = controller->Show(proxy, 0, view->getViewProxy())) {
    vtkSMPVRepresentationProxy::SetScalarColoring(repr, "BoneFraction", vtkDataObject::POINT);
    FrameOutput(view, proxy, 0);
  }
}

void pqBMDockWindow::pollSession() {
  if (!this->Session)
    return;
  qBMSessionWidget* panel = this->Panel->sessionWidget();
  vtkSMProxy* proxy = this->Session->getProxy();
  proxy->UpdatePropertyInformation();
  // The history table lives where the source runs: with the built-in server that is here. The
  // charts take the rows newer than theirs only when the source executed since, and at most
  // every 100 ms: drawing takes the cores the haptic thread needs.
  const vtkIdType frame = vtkSMPropertyHelper(proxy, "FrameInfo").GetAsIdType();
  if (frame != this->ChartedFrame && (this->ForceCharts || this->ChartClock.elapsed() >= 100)) {
    if (auto* logic = vtkBMSessionSource::SafeDownCast(proxy->GetClientSideObject())) {
      this->Panel->chartsWidget()->setHistory(logic->GetHistory());
      this->ChartedFrame = frame;
      this->ChartClock.restart();
    }
  }
  // The state (vtkBMSessionSource's StateInfo is a bm::SessionState) and why it paused (the
  // trial's end, overruns, a device fault, the user).
  panel->setSessionState(
      static_cast<bm::SessionState>(vtkSMPropertyHelper(proxy, "StateInfo").GetAsInt()),
      QString::fromStdString(vtkSMPropertyHelper(proxy, "PauseReasonInfo").GetAsString()));
  panel->setSessionNumbers(vtkSMPropertyHelper(proxy, "TimeInfo").GetAsDouble(),
                           vtkSMPropertyHelper(proxy, "DepthInfo").GetAsDouble(),
                           vtkSMPropertyHelper(proxy, "RemovedVolumeInfo").GetAsDouble(),
                           vtkSMPropertyHelper(proxy, "ThrustInfo").GetAsDouble(),
                           vtkSMPropertyHelper(proxy, "TorqueInfo").GetAsDouble(),
                           vtkSMPropertyHelper(proxy, "FrameMsP99Info").GetAsDouble(),
                           vtkSMPropertyHelper(proxy, "ForceScaleInUseInfo").GetAsDouble());
}
