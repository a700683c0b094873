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

  // Session controls.
  this->SceneComboBox->addItems({QStringLiteral("glenoid"), QStringLiteral("drilling")});
  this->VoxmapResolutionSpinBox->setRange(0, 4096);
  this->VoxmapResolutionSpinBox->setSpecialValueText(qBMPanel::tr("scene's"));
  this->ShellResolutionSpinBox->setRange(0, 4096);
  this->ShellResolutionSpinBox->setSpecialValueText(qBMPanel::tr("scene's"));
  this->ResolutionCostLabel->setText(qBMPanel::tr(
      "Reamer frame time measured on 2 cores (p50): voxmap 96 / shell 170 about 1.3 ms, "
      "192 / 340 (the glenoid scene's) about 6 ms; keep the shell about twice the voxmap's "
      "resolution relative to their sizes (grids 2:1) for an accurate removal."));
  this->DeviceComboBox->addItem(qBMPanel::tr("Scripted"), 0);
  this->DeviceComboBox->addItem(qBMPanel::tr("Mouse proxy"), 1);
  this->ToolDepthSpinBox->setRange(-20.0, 20.0);
  this->ToolDepthSpinBox->setSingleStep(0.1);
  this->ToolDepthSpinBox->setDecimals(2);
  this->ToolDepthSpinBox->setValue(-2.0);
  QObject::connect(this->StartButton, &QPushButton::clicked, q, [q]() {
    Q_EMIT q->startSessionRequested(q->sceneName(), q->voxmapResolution(), q->shellResolution(),
                                    q->deviceType());
  });
  QObject::connect(this->PauseButton, &QPushButton::toggled, q,
                   [q](bool paused) { Q_EMIT q->pauseSessionRequested(paused); });
  QObject::connect(this->StopButton, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->stopSessionRequested(); });
  QObject::connect(this->ToolDepthSpinBox, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q,
                   [q](double depth) { Q_EMIT q->toolDepthChanged(depth); });
  q->setSessionStatus(QString(), false);
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

QString qBMPanel::sceneName() const {
  Q_D(const qBMPanel);
  return d->SceneComboBox->currentText();
}

int qBMPanel::voxmapResolution() const {
  Q_D(const qBMPanel);
  return d->VoxmapResolutionSpinBox->value();
}

int qBMPanel::shellResolution() const {
  Q_D(const qBMPanel);
  return d->ShellResolutionSpinBox->value();
}

int qBMPanel::deviceType() const {
  Q_D(const qBMPanel);
  return d->DeviceComboBox->currentData().toInt();
}

double qBMPanel::toolDepth() const {
  Q_D(const qBMPanel);
  return d->ToolDepthSpinBox->value();
}

void qBMPanel::setVoxmapResolution(int cells) {
  Q_D(qBMPanel);
  d->VoxmapResolutionSpinBox->setValue(cells);
}

void qBMPanel::setShellResolution(int cells) {
  Q_D(qBMPanel);
  d->ShellResolutionSpinBox->setValue(cells);
}

void qBMPanel::setDeviceType(int type) {
  Q_D(qBMPanel);
  const int index = d->DeviceComboBox->findData(type);
  if (index >= 0)
    d->DeviceComboBox->setCurrentIndex(index);
}

void qBMPanel::setSessionNumbers(double timeS, double depthMm, double removedMm3, double thrustN,
                                 double torqueNmm, double frameP99Ms) {
  Q_D(qBMPanel);
  d->SessionNumbersLabel->setText(
      tr("t %1 s, depth %2 mm, removed %3 mm^3\nthrust %4 N, torque %5 N mm, frame p99 %6 ms")
          .arg(timeS, 0, 'f', 2)
          .arg(depthMm, 0, 'f', 2)
          .arg(removedMm3, 0, 'f', 1)
          .arg(thrustN, 0, 'f', 1)
          .arg(torqueNmm, 0, 'f', 0)
          .arg(frameP99Ms, 0, 'f', 2));
}

void qBMPanel::setSessionStatus(const QString& message, bool running) {
  Q_D(qBMPanel);
  d->SessionStatusLabel->setText(message);
  d->StartButton->setEnabled(!running);
  d->PauseButton->setEnabled(running);
  d->StopButton->setEnabled(running);
  if (!running) {
    const QSignalBlocker blocker(d->PauseButton);
    d->PauseButton->setChecked(false);
  }
}
