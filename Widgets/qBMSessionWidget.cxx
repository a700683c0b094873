// qBMSessionWidget.cxx - see qBMSessionWidget.h.
#include "qBMSessionWidget.h"

#include "ui_qBMSessionWidget.h"

#include "bmPanelLogic.h"
#include "bmScene.h"
#include "qBMTouchProbe.h"
#include "vtkBMSessionSource.h"

#include <QFileDialog>
#include <QStandardItemModel>
#include <algorithm>
#include <cmath>
#include <QApplication>
#include <QWheelEvent>

#include <string>

class qBMSessionWidgetPrivate : public Ui_qBMSessionWidget {
  Q_DECLARE_PUBLIC(qBMSessionWidget);

public:
  explicit qBMSessionWidgetPrivate(qBMSessionWidget& object) : q_ptr(&object) {}
  void init();
  void initDevice();
  /// Shows the expected cost of the chosen scene, resolutions and method.
  void updateExpectedCost();
  /// The Pause button as the session's state: checked and reading "Resume" while paused.
  void showPaused(bool paused);
  /// Shows the Touch probe's answer and enables the Touch entry when it is "".
  void showTouchStatus(const QString& status);

  qBMSessionWidget* const q_ptr;
  bm::PanelLogic::ExpectedCost Cost;
  qBMTouchProbe* Probe = nullptr;
  QString TouchStatus = QStringLiteral("probing");
  bool Running = false;
  bool Paused = false; ///< the session is paused (by the user or by itself)
  /// Start is enabled unless a session runs (a paused one is replaced by the new one) or a start
  /// is under way.
  void updateStart() {
    this->StartButton->setEnabled((!this->Running || this->Paused) && !this->Busy);
  }
  bool Busy = false;
};

void qBMSessionWidgetPrivate::init() {
  Q_Q(qBMSessionWidget);
  this->setupUi(q);
  for (const std::string& name : bm::Scene::BuiltinNames())
    this->SceneComboBox->addItem(QString::fromStdString(name));
  this->SceneComboBox->setCurrentText(QStringLiteral("glenoid"));
  this->VoxmapResolutionSpinBox->setRange(0, 4096);
  this->VoxmapResolutionSpinBox->setSpecialValueText(qBMSessionWidget::tr("scene's"));
  this->ShellResolutionSpinBox->setRange(0, 4096);
  this->ShellResolutionSpinBox->setSpecialValueText(qBMSessionWidget::tr("scene's"));
  this->MethodComboBox->addItem(qBMSessionWidget::tr("Scene's"),
                                int(vtkBMSessionSource::SCENE_METHOD));
  this->MethodComboBox->addItem(qBMSessionWidget::tr("Lazar (Faieghi et al.)"),
                                int(vtkBMSessionSource::LAZAR));
  this->MethodComboBox->addItem(qBMSessionWidget::tr("Zheng et al."),
                                int(vtkBMSessionSource::ZHENG));
  const auto cost = [this]() { this->updateExpectedCost(); };
  QObject::connect(this->SceneComboBox, &QComboBox::currentTextChanged, q, cost);
  QObject::connect(this->VoxmapResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   cost);
  QObject::connect(this->ShellResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   cost);
  QObject::connect(this->MethodComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   cost);
  this->updateExpectedCost();
  this->initDevice();

  QObject::connect(this->StartButton, &QPushButton::clicked, q, [q]() {
    Q_EMIT q->startSessionRequested(q->sceneName(), q->voxmapResolution(), q->shellResolution(),
                                    q->deviceType());
  });
  this->showPaused(false);
  QObject::connect(this->PauseButton, &QPushButton::toggled, q, [this, q](bool paused) {
    this->showPaused(paused);
    Q_EMIT q->pauseSessionRequested(paused);
  });
  QObject::connect(this->StopButton, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->stopSessionRequested(); });
  QObject::connect(this->SaveBoneButton, &QPushButton::clicked, q, [this, q]() {
    const QString file =
        QString::fromStdString(bm::PanelLogic::WithVoxmapExtension(q->boneFile().toStdString()));
    this->BoneFileLineEdit->setText(file);
    Q_EMIT q->saveBoneRequested(file);
  });
  QObject::connect(this->BrowseBoneButton, &QPushButton::clicked, q, [this, q]() {
    const QString nrrd = qBMSessionWidget::tr("NRRD voxmap (*.nrrd)");
    const QString mha = qBMSessionWidget::tr("MetaImage voxmap (*.mha)");
    QString chosen = nrrd;
    const QString path = QFileDialog::getSaveFileName(
        q, qBMSessionWidget::tr("Bone file"), this->BoneFileLineEdit->text(), nrrd + ";;" + mha,
        &chosen, QFileDialog::DontConfirmOverwrite);
    if (!path.isEmpty())
      this->BoneFileLineEdit->setText(QString::fromStdString(
          bm::PanelLogic::WithVoxmapExtension(path.toStdString(), chosen == mha ? "mha" : "nrrd")));
  });
  QObject::connect(this->VolumeCheckBox, &QCheckBox::toggled, q,
                   [q](bool on) { Q_EMIT q->volumeRenderingToggled(on); });
  this->StartProgressBar->setRange(0, 0); // busy: no known fraction
  this->StartProgressBar->setVisible(false);
  q->setSessionStatus(QString(), false);
}

void qBMSessionWidgetPrivate::initDevice() {
  Q_Q(qBMSessionWidget);
  this->DeviceComboBox->addItem(qBMSessionWidget::tr("Scripted robot"),
                                int(vtkBMSessionSource::SCRIPTED));
  this->DeviceComboBox->addItem(qBMSessionWidget::tr("Scripted hand"),
                                int(vtkBMSessionSource::HAND));
  this->DeviceComboBox->addItem(qBMSessionWidget::tr("Mouse proxy"),
                                int(vtkBMSessionSource::MOUSE));
  this->DeviceComboBox->addItem(qBMSessionWidget::tr("Touch (OpenHaptics)"),
                                int(vtkBMSessionSource::TOUCH));
  this->showTouchStatus(this->TouchStatus);
  this->Probe = new qBMTouchProbe(q);
  QObject::connect(this->Probe, &qBMTouchProbe::finished, q,
                   [this](const QString& status) { this->showTouchStatus(status); });
  this->Probe->start();

  // 0 reads "per tool": the session takes the tool's (a firm push feeds it at a surgeon's pace).
  this->ForceScaleSpinBox->setRange(0.0, bm::PanelLogic::MaxForceScale());
  this->ForceScaleSpinBox->setDecimals(3);
  this->ForceScaleSpinBox->setSpecialValueText(qBMSessionWidget::tr("per tool"));
  this->ForceScaleSpinBox->setValue(bm::PanelLogic::DefaultForceScale());
  this->ToolDepthSpinBox->setRange(-20.0, 20.0);
  this->ToolDepthSpinBox->setSingleStep(0.1);
  this->ToolDepthSpinBox->setDecimals(2);
  this->ToolDepthSpinBox->setValue(-2.0);
  // The wheel over the depth control moves the depth, never the dock's scroll area (also at the
  // end of the range, where a spin box would pass the wheel on), without a click first while a
  // mouse-proxy session runs (eventFilter). The filter is the application's: ParaView's
  // WheelNeedsFocusBehavior eats, in an application filter of its own, every wheel event of a
  // spin box without the focus, before any filter on the spin box sees it; application filters
  // run last installed first, and this one is installed after ParaView's (when the plugin's dock
  // is made).
  qApp->installEventFilter(q);
  QObject::connect(this->ToolDepthSpinBox, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q,
                   [q](double depth) { Q_EMIT q->toolDepthChanged(depth); });
}

void qBMSessionWidgetPrivate::showTouchStatus(const QString& status) {
  this->TouchStatus = status;
  const bool ready = status.isEmpty();
  if (auto* model = qobject_cast<QStandardItemModel*>(this->DeviceComboBox->model()))
    if (QStandardItem* touch =
            model->item(this->DeviceComboBox->findData(int(vtkBMSessionSource::TOUCH)))) {
      touch->setEnabled(ready);
      touch->setToolTip(status);
    }
  this->TouchStatusLabel->setText(ready ? qBMSessionWidget::tr("Touch: ready.")
                                  : status == QLatin1String("probing")
                                      ? qBMSessionWidget::tr("Touch: probing...")
                                      : qBMSessionWidget::tr("Touch unavailable: %1").arg(status));
}

void qBMSessionWidgetPrivate::updateExpectedCost() {
  Q_Q(qBMSessionWidget);
  this->ResolutionCostLabel->setText(QString::fromStdString(this->Cost.Line(
      q->sceneName().toStdString(), q->voxmapResolution(), q->shellResolution(), q->method())));
}

void qBMSessionWidgetPrivate::showPaused(bool paused) {
  const QSignalBlocker blocker(this->PauseButton);
  this->PauseButton->setChecked(paused);
  this->PauseButton->setText(paused ? qBMSessionWidget::tr("Resume")
                                    : qBMSessionWidget::tr("Pause"));
  this->PauseButton->setToolTip(paused ? qBMSessionWidget::tr("Resume the paused session")
                                       : qBMSessionWidget::tr("Pause the session (zero force on "
                                                              "the device; the cut is kept)"));
}

qBMSessionWidget::qBMSessionWidget(QWidget* parent)
    : Superclass(parent), d_ptr(new qBMSessionWidgetPrivate(*this)) {
  Q_D(qBMSessionWidget);
  d->init();
}

qBMSessionWidget::~qBMSessionWidget() = default;

bool qBMSessionWidget::eventFilter(QObject* watched, QEvent* event) {
  Q_D(qBMSessionWidget);
  // Every event of the application passes here (see initDevice): the type is tested first. The
  // depth control takes the wheel when it has the focus, and without it while a mouse-proxy
  // session runs (the wheel is then the hand on the tool); otherwise ParaView's rule stands and
  // a panel scrolled past it is not changed.
  if (event->type() == QEvent::Wheel &&
      (watched == d->ToolDepthSpinBox ||
       (watched->isWidgetType() &&
        d->ToolDepthSpinBox->isAncestorOf(static_cast<QWidget*>(watched)))) &&
      (d->ToolDepthSpinBox->hasFocus() ||
       (d->Running && this->deviceType() == vtkBMSessionSource::MOUSE))) {
    const int delta = static_cast<QWheelEvent*>(event)->angleDelta().y();
    if (delta != 0)
      this->stepToolDepth(delta > 0 ? 1 : -1);
    event->accept();
    return true;
  }
  return Superclass::eventFilter(watched, event);
}

QString qBMSessionWidget::sceneName() const {
  Q_D(const qBMSessionWidget);
  return d->SceneComboBox->currentText();
}

int qBMSessionWidget::voxmapResolution() const {
  Q_D(const qBMSessionWidget);
  return d->VoxmapResolutionSpinBox->value();
}

int qBMSessionWidget::shellResolution() const {
  Q_D(const qBMSessionWidget);
  return d->ShellResolutionSpinBox->value();
}

int qBMSessionWidget::method() const {
  Q_D(const qBMSessionWidget);
  return d->MethodComboBox->currentData().toInt();
}

bool qBMSessionWidget::useChosenTool() const {
  Q_D(const qBMSessionWidget);
  return d->UseToolCheckBox->isChecked();
}

int qBMSessionWidget::deviceType() const {
  Q_D(const qBMSessionWidget);
  return d->DeviceComboBox->currentData().toInt();
}

double qBMSessionWidget::forceScale() const {
  Q_D(const qBMSessionWidget);
  return d->ForceScaleSpinBox->value();
}

double qBMSessionWidget::toolDepth() const {
  Q_D(const qBMSessionWidget);
  return d->ToolDepthSpinBox->value();
}

QString qBMSessionWidget::boneFile() const {
  Q_D(const qBMSessionWidget);
  return d->BoneFileLineEdit->text();
}

bool qBMSessionWidget::startFromBoneFile() const {
  Q_D(const qBMSessionWidget);
  return d->StartFromFileCheckBox->isChecked();
}

bool qBMSessionWidget::volumeRendering() const {
  Q_D(const qBMSessionWidget);
  return d->VolumeCheckBox->isChecked();
}

QString qBMSessionWidget::expectedCost() const {
  Q_D(const qBMSessionWidget);
  return d->ResolutionCostLabel->text();
}

QString qBMSessionWidget::touchStatus() const {
  Q_D(const qBMSessionWidget);
  return d->TouchStatus;
}

QString qBMSessionWidget::sessionStatus() const {
  Q_D(const qBMSessionWidget);
  return d->SessionStatusLabel->text();
}

bool qBMSessionWidget::isBusy() const {
  Q_D(const qBMSessionWidget);
  return d->Busy;
}

qBMTouchProbe* qBMSessionWidget::touchProbe() const {
  Q_D(const qBMSessionWidget);
  return d->Probe;
}

void qBMSessionWidget::setVoxmapResolution(int cells) {
  Q_D(qBMSessionWidget);
  d->VoxmapResolutionSpinBox->setValue(cells);
}

void qBMSessionWidget::setShellResolution(int cells) {
  Q_D(qBMSessionWidget);
  d->ShellResolutionSpinBox->setValue(cells);
}

void qBMSessionWidget::setDeviceType(int type) {
  Q_D(qBMSessionWidget);
  const int index = d->DeviceComboBox->findData(type);
  if (index >= 0)
    d->DeviceComboBox->setCurrentIndex(index);
}

void qBMSessionWidget::setMethod(int method) {
  Q_D(qBMSessionWidget);
  const int index = d->MethodComboBox->findData(method);
  if (index >= 0)
    d->MethodComboBox->setCurrentIndex(index);
}

void qBMSessionWidget::setUseChosenTool(bool use) {
  Q_D(qBMSessionWidget);
  d->UseToolCheckBox->setChecked(use);
}

void qBMSessionWidget::setForceScale(double scale) {
  Q_D(qBMSessionWidget);
  d->ForceScaleSpinBox->setValue(scale);
}

void qBMSessionWidget::setToolDepth(double depthMm) {
  Q_D(qBMSessionWidget);
  d->ToolDepthSpinBox->setValue(depthMm);
}

void qBMSessionWidget::stepToolDepth(int steps) {
  Q_D(qBMSessionWidget);
  d->ToolDepthSpinBox->stepBy(steps);
}

void qBMSessionWidget::setBoneFile(const QString& path) {
  Q_D(qBMSessionWidget);
  d->BoneFileLineEdit->setText(path);
}

void qBMSessionWidget::setStartFromBoneFile(bool start) {
  Q_D(qBMSessionWidget);
  d->StartFromFileCheckBox->setChecked(start);
}

void qBMSessionWidget::setVolumeRendering(bool on) {
  Q_D(qBMSessionWidget);
  d->VolumeCheckBox->setChecked(on);
}

void qBMSessionWidget::setSessionNumbers(double timeS, double depthMm, double removedMm3,
                                         double thrustN, double torqueNmm, double frameP99Ms,
                                         double forceScale) {
  Q_D(qBMSessionWidget);
  QString text =
      tr("t %1 s, depth %2 mm, removed %3 mm^3\nthrust %4 N, torque %5 N mm, haptic frame p99 "
         "%6 ms")
          .arg(timeS, 0, 'f', 2)
          .arg(depthMm, 0, 'f', 2)
          .arg(removedMm3, 0, 'f', 1)
          .arg(thrustN, 0, 'f', 1)
          .arg(torqueNmm, 0, 'f', 0)
          .arg(frameP99Ms, 0, 'f', 2);
  if (forceScale > 0)
    text += tr(", force scale %1").arg(forceScale, 0, 'g', 3);
  d->SessionNumbersLabel->setText(text);
}

void qBMSessionWidget::setSessionState(bm::SessionState state, const QString& pauseReason) {
  Q_D(qBMSessionWidget);
  const QString text =
      QString::fromStdString(bm::PanelLogic::StateText(state, pauseReason.toStdString()));
  d->SessionStateLabel->setText(text.isEmpty() ? QString() : tr("Session %1").arg(text));
  d->Paused = bm::PanelLogic::IsPaused(state);
  d->showPaused(d->Paused);
  d->updateStart();
}

void qBMSessionWidget::setSessionStatus(const QString& message, bool running) {
  Q_D(qBMSessionWidget);
  d->SessionStatusLabel->setText(message);
  d->Running = running;
  d->PauseButton->setEnabled(running);
  d->StopButton->setEnabled(running);
  if (!running) {
    d->Paused = false;
    d->showPaused(false);
  }
  d->updateStart();
}

void qBMSessionWidget::setBusyProgress(double fraction, const QString& stage) {
  Q_D(qBMSessionWidget);
  if (fraction < 0) {
    d->StartProgressBar->setRange(0, 0);
  } else {
    d->StartProgressBar->setRange(0, 100);
    d->StartProgressBar->setValue(int(std::lround(100 * std::clamp(fraction, 0.0, 1.0))));
  }
  if (!stage.isEmpty())
    d->StartProgressBar->setFormat(tr("%1: %p%").arg(stage));
}

void qBMSessionWidget::setBusy(bool busy, const QString& message) {
  Q_D(qBMSessionWidget);
  d->Busy = busy;
  d->StartProgressBar->setVisible(busy);
  if (busy) {
    d->StartProgressBar->setRange(0, 0); // no fraction known yet
    d->StartProgressBar->setFormat("%p%");
  }
  // Stop cancels a start under way.
  d->StopButton->setEnabled(busy || d->Running);
  if (!message.isEmpty())
    d->SessionStatusLabel->setText(message);
  d->updateStart();
}
