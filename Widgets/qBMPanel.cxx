// qBMPanel.cxx - see qBMPanel.h.
#include "qBMPanel.h"

#include "ui_qBMPanel.h"

#include "vtkBMToolSource.h"
#include "vtkNew.h"

class qBMPanelPrivate : public Ui_qBMPanel {
  Q_DECLARE_PUBLIC(qBMPanel);

public:
  explicit qBMPanelPrivate(qBMPanel& object) : q_ptr(&object) {}
  void init();
  /// Shows the logic's description of the chosen tool.
  void updateSummary();

  qBMPanel* const q_ptr;
  /// The logic the panel is bound to: holds the chosen tool and describes it.
  vtkNew<vtkBMToolSource> Logic;
};

void qBMPanelPrivate::init() {
  Q_Q(qBMPanel);
  this->setupUi(q);
  // Item order follows vtkBMToolSource::ToolTypes.
  this->ToolTypeComboBox->clear();
  this->ToolTypeComboBox->addItem(qBMPanel::tr("Twist drill"), int(vtkBMToolSource::DRILL));
  this->ToolTypeComboBox->addItem(qBMPanel::tr("Glenoid reamer"), int(vtkBMToolSource::REAMER));
  this->ToolTypeComboBox->addItem(qBMPanel::tr("Spherical burr"), int(vtkBMToolSource::BURR));
  this->ToolTypeComboBox->setCurrentIndex(this->Logic->GetToolType());
  this->ResolutionSpinBox->setRange(3, 1024);
  this->ResolutionSpinBox->setValue(this->Logic->GetResolution());

  QObject::connect(this->ToolTypeComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   &qBMPanel::setToolType);
  QObject::connect(this->ResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   &qBMPanel::setResolution);
  QObject::connect(this->AddToolButton, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->addToolRequested(q->toolType(), q->resolution()); });
  this->updateSummary();
}

void qBMPanelPrivate::updateSummary() {
  Q_Q(qBMPanel);
  this->ToolSummaryLabel->setText(q->toolSummary());
}

qBMPanel::qBMPanel(QWidget* parent) : Superclass(parent), d_ptr(new qBMPanelPrivate(*this)) {
  Q_D(qBMPanel);
  d->init();
}

qBMPanel::~qBMPanel() = default;

int qBMPanel::toolType() const {
  Q_D(const qBMPanel);
  return d->Logic->GetToolType();
}

int qBMPanel::resolution() const {
  Q_D(const qBMPanel);
  return d->Logic->GetResolution();
}

QString qBMPanel::toolSummary() const {
  Q_D(const qBMPanel);
  vtkBMToolSource* logic = d->Logic;
  if (!logic->GetToolIsValid())
    return tr("Invalid tool parameters: %1").arg(QString::fromUtf8(logic->GetToolError()));
  double range[2];
  logic->GetAxialRange(range);
  return tr("%1 lips, outer radius %2 mm, length %3 mm")
      .arg(logic->GetNumberOfLips())
      .arg(logic->GetOuterRadius(), 0, 'f', 2)
      .arg(range[1] - range[0], 0, 'f', 2);
}

void qBMPanel::setToolType(int type) {
  Q_D(qBMPanel);
  if (type < vtkBMToolSource::DRILL || type > vtkBMToolSource::BURR || type == toolType())
    return;
  d->Logic->SetToolType(type);
  const QSignalBlocker blocker(d->ToolTypeComboBox);
  d->ToolTypeComboBox->setCurrentIndex(type);
  d->updateSummary();
  Q_EMIT toolTypeChanged(type);
}

QString qBMPanel::statusMessage() const {
  Q_D(const qBMPanel);
  return d->StatusLabel->text();
}

void qBMPanel::setStatusMessage(const QString& message) {
  Q_D(qBMPanel);
  d->StatusLabel->setText(message);
}

void qBMPanel::setResolution(int facets) {
  Q_D(qBMPanel);
  d->Logic->SetResolution(facets);
  const QSignalBlocker blocker(d->ResolutionSpinBox);
  d->ResolutionSpinBox->setValue(d->Logic->GetResolution());
}
