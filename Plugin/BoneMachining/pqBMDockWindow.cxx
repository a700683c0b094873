// pqBMDockWindow.cxx - see pqBMDockWindow.h.
#include "pqBMDockWindow.h"

#include "qBMPanel.h"
#include "vtkBMSessionSource.h"

#include "pqActiveObjects.h"
#include "pqApplicationCore.h"
#include "pqObjectBuilder.h"
#include "pqPipelineSource.h"
#include "pqServer.h"
#include "pqUndoStack.h"
#include "pqView.h"
#include "vtkDataObject.h"
#include "vtkNew.h"
#include "vtkSMParaViewPipelineControllerWithRendering.h"
#include "vtkSMPVRepresentationProxy.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMViewProxy.h"

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
  QObject::connect(this->Panel, &qBMPanel::addToolRequested, this, &pqBMDockWindow::addTool);
  QObject::connect(this->Panel, &qBMPanel::startSessionRequested, this,
                   &pqBMDockWindow::startSession);
  QObject::connect(this->Panel, &qBMPanel::pauseSessionRequested, this,
                   &pqBMDockWindow::pauseSession);
  QObject::connect(this->Panel, &qBMPanel::stopSessionRequested, this,
                   &pqBMDockWindow::stopSession);
  QObject::connect(this->Panel, &qBMPanel::toolDepthChanged, this, &pqBMDockWindow::setToolDepth);
  QObject::connect(this->Panel, &qBMPanel::saveBoneRequested, this, &pqBMDockWindow::saveBone);
  QObject::connect(this->Panel, &qBMPanel::volumeRenderingToggled, this,
                   &pqBMDockWindow::setVolumeRendering);
  QObject::connect(this->Panel, &qBMPanel::previewCTRequested, this, &pqBMDockWindow::previewCT);
  this->Poll->setInterval(33);
  QObject::connect(this->Poll, &QTimer::timeout, this, &pqBMDockWindow::pollSession);
}

pqBMDockWindow::~pqBMDockWindow() = default;

void pqBMDockWindow::addTool(int toolType, int resolution) {
  pqServer* server = pqActiveObjects::instance().activeServer();
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
    vtkSMPropertyHelper(proxy, "Parameters")
        .Set(this->Panel->toolSpecification().toUtf8().constData());
    proxy->UpdateVTKObjects();
    source->updatePipeline();
    source->setModifiedState(pqProxy::UNMODIFIED);
    if (pqView* view = pqActiveObjects::instance().activeView()) {
      vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
      controller->Show(proxy, 0, view->getViewProxy());
      view->resetDisplay();
      view->render();
    }
    pqActiveObjects::instance().setActiveSource(source);
    this->Panel->setStatusMessage(tr("Added %1 to the pipeline.").arg(source->getSMName()));
  } else {
    this->Panel->setStatusMessage(tr("Could not create a BM Tool source: is the plugin loaded "
                                     "on the server?"));
  }
  END_UNDO_SET();
}

void pqBMDockWindow::startSession(const QString& scene, int voxmapResolution, int shellResolution,
                                  int deviceType) {
  pqServer* server = pqActiveObjects::instance().activeServer();
  if (!server)
    return;
  if (this->Panel->useChosenTool() && this->Panel->toolSpecification().isEmpty()) {
    // Refused before any source is made: the scene's tool must not stand in silently.
    this->Panel->setSessionStatus(tr("Cannot start: %1").arg(this->Panel->toolSummary()), false);
    return;
  }
  std::string boneCT;
  if (this->Panel->useCTBone()) {
    this->previewCT(); // the CT settings as they are now, checked before the session starts
    if (!this->CTBone) {
      this->Panel->setSessionStatus(tr("Cannot start: no BM CT Bone source."), false);
      return;
    }
    vtkSMProxy* ct = this->CTBone->getProxy();
    const std::string error = vtkSMPropertyHelper(ct, "LastErrorInfo").GetAsString();
    if (!error.empty()) {
      this->Panel->setSessionStatus(
          tr("Cannot start on the CT bone: %1").arg(QString::fromStdString(error)), false);
      return;
    }
    boneCT = vtkSMPropertyHelper(ct, "BoneSpecificationInfo").GetAsString();
  }
  pqPipelineSource* source = pqApplicationCore::instance()->getObjectBuilder()->createSource(
      "sources", "BMSessionSource", server);
  if (!source) {
    this->Panel->setSessionStatus(tr("Could not create a BM Session source."), false);
    return;
  }
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(source->getProxy());
  vtkSMPropertyHelper(proxy, "Scene").Set(scene.toUtf8().constData());
  vtkSMPropertyHelper(proxy, "VoxmapResolution").Set(voxmapResolution);
  vtkSMPropertyHelper(proxy, "ShellResolution").Set(shellResolution);
  vtkSMPropertyHelper(proxy, "DeviceType").Set(deviceType);
  vtkSMPropertyHelper(proxy, "ToolDepth").Set(this->Panel->toolDepth());
  vtkSMPropertyHelper(proxy, "Method").Set(this->Panel->method());
  vtkSMPropertyHelper(proxy, "Tool")
      .Set(this->Panel->useChosenTool() ? this->Panel->toolSpecification().toUtf8().constData()
                                        : "");
  vtkSMPropertyHelper(proxy, "BoneFile")
      .Set(this->Panel->startFromBoneFile() ? this->Panel->boneFile().toUtf8().constData() : "");
  vtkSMPropertyHelper(proxy, "VolumeOutput").Set(this->Panel->volumeRendering() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "BoneCT").Set(boneCT.c_str());
  vtkSMPropertyHelper(proxy, "OverrideTrial").Set(this->Panel->useCTBone() ? 1 : 0);
  vtkSMPropertyHelper(proxy, "Entry").Set(this->Panel->entry().constData(), 3);
  vtkSMPropertyHelper(proxy, "Axis").Set(this->Panel->axis().constData(), 3);
  proxy->UpdateVTKObjects();
  proxy->InvokeCommand("Start");
  proxy->UpdatePropertyInformation();
  const std::string error = vtkSMPropertyHelper(proxy, "LastErrorInfo").GetAsString();
  if (!error.empty()) { // Start() failed (bad scene, import error)
    this->Panel->setSessionStatus(
        tr("Could not start %1: %2").arg(source->getSMName(), QString::fromStdString(error)),
        false);
    return;
  }
  source->updatePipeline();
  source->setModifiedState(pqProxy::UNMODIFIED);
  if (pqView* view = pqActiveObjects::instance().activeView()) {
    vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
    controller->Show(proxy, 0, view->getViewProxy());
    controller->Show(proxy, 1, view->getViewProxy());
    this->Session = source;
    if (this->Panel->volumeRendering())
      this->setVolumeRendering(true);
    view->resetDisplay();
    view->render();
  }
  this->Session = source;
  this->ChartedFrame = -1;
  this->ChartClock.start();
  this->Poll->start();
  this->Panel->setSessionStatus(tr("Started %1.").arg(source->getSMName()), true);
}

void pqBMDockWindow::pauseSession(bool paused) {
  if (!this->Session)
    return;
  this->Session->getProxy()->InvokeCommand(paused ? "Pause" : "Resume");
  this->Panel->setSessionStatus(
      (paused ? tr("Paused %1.") : tr("Resumed %1.")).arg(this->Session->getSMName()), true);
}

void pqBMDockWindow::stopSession() {
  this->Poll->stop();
  if (!this->Session)
    return;
  this->Session->getProxy()->InvokeCommand("Stop");
  this->Session->updatePipeline(); // the final cut, numbers and state
  this->ForceCharts = true;
  this->pollSession();
  this->ForceCharts = false;
  this->Panel->setSessionStatus(tr("Stopped %1.").arg(this->Session->getSMName()), false);
}

void pqBMDockWindow::setToolDepth(double depthMm) {
  if (!this->Session)
    return;
  vtkSMProxy* proxy = this->Session->getProxy();
  vtkSMPropertyHelper(proxy, "ToolDepth").Set(depthMm);
  proxy->UpdateVTKObjects();
}

void pqBMDockWindow::saveBone(const QString& path) {
  if (!this->Session) {
    this->Panel->setSessionStatus(tr("No session bone to save: start a session first."), false);
    return;
  }
  if (path.isEmpty()) {
    this->Panel->setSessionStatus(tr("Choose a bone file (.nrrd or .mha) to save to."),
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
  this->Panel->setSessionStatus(
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
    controller->Show(proxy, 0, view->getViewProxy());
  }
  view->render();
}

void pqBMDockWindow::previewCT() {
  pqServer* server = pqActiveObjects::instance().activeServer();
  if (!server)
    return;
  if (!this->CTBone) {
    this->CTBone = pqApplicationCore::instance()->getObjectBuilder()->createSource(
        "sources", "BMCTBoneSource", server);
    if (!this->CTBone) {
      this->Panel->setCTPreview(0, 0, {}, {}, tr("could not create a BM CT Bone source"));
      return;
    }
  }
  vtkSMSourceProxy* proxy = vtkSMSourceProxy::SafeDownCast(this->CTBone->getProxy());
  vtkSMPropertyHelper(proxy, "FileName").Set(this->Panel->ctFileName().toUtf8().constData());
  vtkSMPropertyHelper(proxy, "ThresholdHU").Set(this->Panel->thresholdHU());
  vtkSMPropertyHelper(proxy, "ROI").Set(this->Panel->roi().constData(), 6);
  vtkSMPropertyHelper(proxy, "Resolution").Set(this->Panel->ctResolution());
  vtkSMPropertyHelper(proxy, "Axis").Set(this->Panel->axis().constData(), 3);
  proxy->UpdateVTKObjects();
  this->CTBone->updatePipeline();
  this->CTBone->setModifiedState(pqProxy::UNMODIFIED);
  proxy->UpdatePropertyInformation();
  const QString error =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "LastErrorInfo").GetAsString());
  QVector<double> bounds(6), entry(3);
  vtkSMPropertyHelper(proxy, "BoneBoundsInfo").Get(bounds.data(), 6);
  vtkSMPropertyHelper(proxy, "SuggestedEntryInfo").Get(entry.data(), 3);
  this->Panel->setCTPreview(vtkSMPropertyHelper(proxy, "BoneVoxelsInfo").GetAsIdType(),
                            vtkSMPropertyHelper(proxy, "BoneVolumeInfo").GetAsDouble(), bounds,
                            entry, error);
  pqView* view = pqActiveObjects::instance().activeView();
  if (!view || !error.isEmpty())
    return;
  vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
  if (vtkSMProxy* repr = controller->Show(proxy, 0, view->getViewProxy())) {
    vtkSMPVRepresentationProxy::SetScalarColoring(repr, "BoneFraction", vtkDataObject::POINT);
    vtkSMPropertyHelper(repr, "Representation").Set("Slice");
    repr->UpdateVTKObjects();
  }
  view->resetDisplay();
  view->render();
}

void pqBMDockWindow::pollSession() {
  if (!this->Session)
    return;
  vtkSMProxy* proxy = this->Session->getProxy();
  proxy->UpdatePropertyInformation();
  // The history table lives where the source runs: with the built-in server that is here. The
  // charts are redrawn only when the source executed since, and at most every 100 ms: drawing
  // takes the cores the haptic thread needs.
  const vtkIdType frame = vtkSMPropertyHelper(proxy, "FrameInfo").GetAsIdType();
  if (frame != this->ChartedFrame && (this->ForceCharts || this->ChartClock.elapsed() >= 100)) {
    if (auto* logic = vtkBMSessionSource::SafeDownCast(proxy->GetClientSideObject())) {
      this->Panel->setHistory(logic->GetHistory());
      this->ChartedFrame = frame;
      this->ChartClock.restart();
    }
  }
  // The state, and why it paused (the trial's end, overruns, a device fault, the user).
  const int state = vtkSMPropertyHelper(proxy, "StateInfo").GetAsInt();
  const QString reason =
      QString::fromStdString(vtkSMPropertyHelper(proxy, "PauseReasonInfo").GetAsString());
  this->Panel->setSessionState(state == 1   ? tr("running")
                               : state == 2 ? tr("paused: %1").arg(reason)
                               : state == 3 ? tr("stopped")
                                            : QString());
  this->Panel->setSessionNumbers(vtkSMPropertyHelper(proxy, "TimeInfo").GetAsDouble(),
                                 vtkSMPropertyHelper(proxy, "DepthInfo").GetAsDouble(),
                                 vtkSMPropertyHelper(proxy, "RemovedVolumeInfo").GetAsDouble(),
                                 vtkSMPropertyHelper(proxy, "ThrustInfo").GetAsDouble(),
                                 vtkSMPropertyHelper(proxy, "TorqueInfo").GetAsDouble(),
                                 vtkSMPropertyHelper(proxy, "FrameMsP99Info").GetAsDouble());
}
