// qBMPanel.cxx - see qBMPanel.h.
#include "qBMPanel.h"

#include "qBMCTWidget.h"
#include "qBMChartsWidget.h"
#include "qBMPlanWidget.h"
#include "qBMSessionWidget.h"
#include "qBMToolWidget.h"

#include <QVBoxLayout>

class qBMPanelPrivate {
public:
  qBMToolWidget* Tool = nullptr;
  qBMCTWidget* CT = nullptr;
  qBMPlanWidget* Plan = nullptr;
  qBMSessionWidget* Session = nullptr;
  qBMChartsWidget* Charts = nullptr;
};

qBMPanel::qBMPanel(QWidget* parent) : Superclass(parent), d_ptr(new qBMPanelPrivate) {
  Q_D(qBMPanel);
  this->setObjectName("qBMPanel");
  this->setWindowTitle(tr("Bone Machining"));
  auto* layout = new QVBoxLayout(this);
  layout->setObjectName("MainLayout");
  d->Tool = new qBMToolWidget(this);
  d->CT = new qBMCTWidget(this);
  d->Plan = new qBMPlanWidget(this);
  d->Session = new qBMSessionWidget(this);
  d->Charts = new qBMChartsWidget(this);
  d->Charts->setObjectName("ChartsWidget");
  layout->addWidget(d->Tool);
  layout->addWidget(d->CT);
  layout->addWidget(d->Plan);
  layout->addWidget(d->Session);
  layout->addWidget(d->Charts);
  layout->addStretch(1);
}

qBMPanel::~qBMPanel() = default;

qBMToolWidget* qBMPanel::toolWidget() const {
  Q_D(const qBMPanel);
  return d->Tool;
}

qBMCTWidget* qBMPanel::ctWidget() const {
  Q_D(const qBMPanel);
  return d->CT;
}

qBMPlanWidget* qBMPanel::planWidget() const {
  Q_D(const qBMPanel);
  return d->Plan;
}

qBMSessionWidget* qBMPanel::sessionWidget() const {
  Q_D(const qBMPanel);
  return d->Session;
}

qBMChartsWidget* qBMPanel::chartsWidget() const {
  Q_D(const qBMPanel);
  return d->Charts;
}
