// pqBMDockWindow.cxx - see pqBMDockWindow.h.
#include "pqBMDockWindow.h"

#include "qBMPanel.h"

#include "pqActiveObjects.h"
#include "pqApplicationCore.h"
#include "pqObjectBuilder.h"
#include "pqPipelineSource.h"
#include "pqServer.h"
#include "pqUndoStack.h"
#include "pqView.h"
#include "vtkNew.h"
#include "vtkSMParaViewPipelineControllerWithRendering.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMViewProxy.h"

#include <QScrollArea>

pqBMDockWindow::pqBMDockWindow(QWidget* parent)
    : Superclass(tr("Bone Machining"), parent), Panel(new qBMPanel) {
  // Object names make the widgets addressable by ParaView's XML GUI tests (Testing/GUI).
  auto* scroll = new QScrollArea(this);
  scroll->setObjectName("ScrollArea");
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setWidget(this->Panel);
  this->setWidget(scroll);
  QObject::connect(this->Panel, &qBMPanel::addToolRequested, this, &pqBMDockWindow::addTool);
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
