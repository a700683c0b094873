// qBMCTWidget.cxx - see qBMCTWidget.h.
#include "qBMCTWidget.h"

#include "ui_qBMCTWidget.h"

#include "bmPanelLogic.h"
#ifdef BM_WITH_DCMTK
#include "qBMPacsBrowser.h"
#endif

#include <QComboBox>
#include <QFileDialog>

#include <string>
#include <vector>

class qBMCTWidgetPrivate : public Ui_qBMCTWidget {
  Q_DECLARE_PUBLIC(qBMCTWidget);

public:
  explicit qBMCTWidgetPrivate(qBMCTWidget& object) : q_ptr(&object) {}
  void init();
  QVector<QDoubleSpinBox*> roiBoxes() const {
    return {this->RoiX0SpinBox, this->RoiY0SpinBox, this->RoiZ0SpinBox,
            this->RoiX1SpinBox, this->RoiY1SpinBox, this->RoiZ1SpinBox};
  }
  QVector<QDoubleSpinBox*> axisBoxes() const {
    return {this->AxisXSpinBox, this->AxisYSpinBox, this->AxisZSpinBox};
  }
  QVector<QDoubleSpinBox*> entryBoxes() const {
    return {this->EntryXSpinBox, this->EntryYSpinBox, this->EntryZSpinBox};
  }
  QVector<QDoubleSpinBox*> seedBoxes() const {
    return {this->SeedXSpinBox, this->SeedYSpinBox, this->SeedZSpinBox};
  }
  QVector<QDoubleSpinBox*> boxCentreBoxes() const {
    return {this->BoxCentreXSpinBox, this->BoxCentreYSpinBox, this->BoxCentreZSpinBox};
  }
  QVector<QDoubleSpinBox*> boxHalfBoxes() const {
    return {this->BoxHalfXSpinBox, this->BoxHalfYSpinBox, this->BoxHalfZSpinBox};
  }
  QVector<QDoubleSpinBox*> boxRotationBoxes() const {
    return {this->BoxRotationXSpinBox, this->BoxRotationYSpinBox, this->BoxRotationZSpinBox};
  }
  static QVector<double> values(const QVector<QDoubleSpinBox*>& boxes) {
    QVector<double> v;
    for (QDoubleSpinBox* box : boxes)
      v.append(box->value());
    return v;
  }
  static void setValues(const QVector<QDoubleSpinBox*>& boxes, const QVector<double>& v) {
    for (int i = 0; i < boxes.size() && i < v.size(); ++i)
      boxes[i]->setValue(v[i]);
  }

  qBMCTWidget* const q_ptr;
  /// The PACS study browser (nullptr without DCMTK).
  qBMPacsBrowser* PacsBrowser = nullptr;
  /// The last preview's suggested entry point, mm (empty: none yet).
  QVector<double> SuggestedEntry;
};

void qBMCTWidgetPrivate::init() {
  Q_Q(qBMCTWidget);
  this->setupUi(q);
  this->ThresholdSpinBox->setRange(-2000.0, 10000.0);
  this->ThresholdSpinBox->setDecimals(0);
  this->ThresholdSpinBox->setSingleStep(50.0);
  this->ThresholdSpinBox->setValue(200.0);
  this->HUSlopeSpinBox->setRange(-10000.0, 10000.0);
  this->HUSlopeSpinBox->setDecimals(4);
  this->HUSlopeSpinBox->setValue(1.0);
  this->HUInterceptSpinBox->setRange(-100000.0, 100000.0);
  this->HUInterceptSpinBox->setDecimals(1);
  this->HUInterceptSpinBox->setValue(-1024.0);
  // The threshold's unit and the mapping's boxes follow the intensity mode.
  auto showMode = [this](int mode) {
    this->ThresholdLabel->setText(mode == 1 ? qBMCTWidget::tr("Threshold (file units):")
                                            : qBMCTWidget::tr("Threshold (HU):"));
    this->HUSlopeSpinBox->setVisible(mode == 2);
    this->HUInterceptSpinBox->setVisible(mode == 2);
  };
  QObject::connect(this->IntensityComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   showMode);
  showMode(0);
  for (QDoubleSpinBox* box :
       this->roiBoxes() + this->entryBoxes() + this->seedBoxes() + this->boxCentreBoxes()) {
    box->setRange(-10000.0, 10000.0);
    box->setDecimals(2);
  }
  for (QDoubleSpinBox* box : this->axisBoxes()) {
    box->setRange(-1.0, 1.0);
    box->setDecimals(3);
    box->setSingleStep(0.1);
  }
  this->AxisZSpinBox->setValue(1.0);
  for (QDoubleSpinBox* box : this->boxHalfBoxes()) {
    box->setRange(0.01, 10000.0);
    box->setDecimals(2);
    box->setValue(50.0);
  }
  for (QDoubleSpinBox* box : this->boxRotationBoxes()) {
    box->setRange(-360.0, 360.0);
    box->setDecimals(1);
    box->setSingleStep(5.0);
  }
  this->CTResolutionSpinBox->setRange(8, 1024);
  this->CTResolutionSpinBox->setValue(96);
  this->UseSuggestedEntryButton->setEnabled(false);
  QObject::connect(this->PreviewCTButton, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->previewCTRequested(); });
  QObject::connect(this->UseSuggestedEntryButton, &QPushButton::clicked, q,
                   [this, q]() { q->setEntry(this->SuggestedEntry); });
  QObject::connect(this->BrowseCTFileButton, &QPushButton::clicked, q, [this, q]() {
    // Every format the import reads (bm::PanelLogic::CTFileFilter: the readers' own lists).
    const QString path =
        QFileDialog::getOpenFileName(q, qBMCTWidget::tr("CT file"), this->CTFileLineEdit->text(),
                                     QString::fromStdString(bm::PanelLogic::CTFileFilter()));
    if (!path.isEmpty())
      this->CTFileLineEdit->setText(path);
  });
  QObject::connect(this->BrowseCTFolderButton, &QPushButton::clicked, q, [this, q]() {
    const QString path = QFileDialog::getExistingDirectory(q, qBMCTWidget::tr("DICOM folder"),
                                                           this->CTFileLineEdit->text());
    if (!path.isEmpty())
      this->CTFileLineEdit->setText(path);
  });
#ifdef BM_WITH_DCMTK
  // A series fetched from a PACS is the CT exactly as a DICOM folder chosen above.
  auto* fromPacs = new QPushButton(qBMCTWidget::tr("From PACS..."), q);
  fromPacs->setObjectName("FromPacsButton");
  fromPacs->setToolTip(qBMCTWidget::tr("Find a CT series on a PACS and fetch it"));
  this->CTBrowseLayout->addWidget(fromPacs);
  this->PacsBrowser = new qBMPacsBrowser(q);
  QObject::connect(fromPacs, &QPushButton::clicked, q, [this]() {
    this->PacsBrowser->show();
    this->PacsBrowser->raise();
    this->PacsBrowser->activateWindow();
  });
  QObject::connect(this->PacsBrowser, &qBMPacsBrowser::seriesFetched, q,
                   [this](const QString& folder) { this->CTFileLineEdit->setText(folder); });
#endif
}

qBMCTWidget::qBMCTWidget(QWidget* parent)
    : Superclass(parent), d_ptr(new qBMCTWidgetPrivate(*this)) {
  Q_D(qBMCTWidget);
  d->init();
}

qBMCTWidget::~qBMCTWidget() = default;

QString qBMCTWidget::ctFileName() const {
  Q_D(const qBMCTWidget);
  return d->CTFileLineEdit->text();
}

qBMPacsBrowser* qBMCTWidget::pacsBrowser() const {
  Q_D(const qBMCTWidget);
  return d->PacsBrowser;
}

double qBMCTWidget::thresholdHU() const {
  Q_D(const qBMCTWidget);
  return d->ThresholdSpinBox->value();
}

int qBMCTWidget::intensityMode() const {
  Q_D(const qBMCTWidget);
  return d->IntensityComboBox->currentIndex();
}

QVector<double> qBMCTWidget::huMapping() const {
  Q_D(const qBMCTWidget);
  return {d->HUSlopeSpinBox->value(), d->HUInterceptSpinBox->value()};
}

void qBMCTWidget::setIntensityMode(int mode) {
  Q_D(qBMCTWidget);
  d->IntensityComboBox->setCurrentIndex(mode);
}

QVector<double> qBMCTWidget::roi() const {
  Q_D(const qBMCTWidget);
  return d->values(d->roiBoxes());
}

int qBMCTWidget::ctResolution() const {
  Q_D(const qBMCTWidget);
  return d->CTResolutionSpinBox->value();
}

QVector<double> qBMCTWidget::axis() const {
  Q_D(const qBMCTWidget);
  return d->values(d->axisBoxes());
}

QVector<double> qBMCTWidget::entry() const {
  Q_D(const qBMCTWidget);
  return d->values(d->entryBoxes());
}

bool qBMCTWidget::useCTBone() const {
  Q_D(const qBMCTWidget);
  return d->UseCTCheckBox->isChecked();
}

void qBMCTWidget::setCTFileName(const QString& path) {
  Q_D(qBMCTWidget);
  d->CTFileLineEdit->setText(path);
}

void qBMCTWidget::setThresholdHU(double hu) {
  Q_D(qBMCTWidget);
  d->ThresholdSpinBox->setValue(hu);
}

void qBMCTWidget::setRoi(const QVector<double>& box) {
  Q_D(qBMCTWidget);
  d->setValues(d->roiBoxes(), box);
}

void qBMCTWidget::setAxis(const QVector<double>& axis) {
  Q_D(qBMCTWidget);
  d->setValues(d->axisBoxes(), axis);
}

void qBMCTWidget::setEntry(const QVector<double>& entry) {
  Q_D(qBMCTWidget);
  d->setValues(d->entryBoxes(), entry);
}

void qBMCTWidget::setUseCTBone(bool use) {
  Q_D(qBMCTWidget);
  d->UseCTCheckBox->setChecked(use);
}

bool qBMCTWidget::keepAllBones() const {
  Q_D(const qBMCTWidget);
  return d->KeepAllBonesCheckBox->isChecked();
}

void qBMCTWidget::setKeepAllBones(bool keep) {
  Q_D(qBMCTWidget);
  d->KeepAllBonesCheckBox->setChecked(keep);
}

bool qBMCTWidget::useSeed() const {
  Q_D(const qBMCTWidget);
  return d->UseSeedCheckBox->isChecked();
}

QVector<double> qBMCTWidget::seed() const {
  Q_D(const qBMCTWidget);
  return d->values(d->seedBoxes());
}

bool qBMCTWidget::useBox() const {
  Q_D(const qBMCTWidget);
  return d->UseBoxCheckBox->isChecked();
}

QVector<double> qBMCTWidget::boxCentre() const {
  Q_D(const qBMCTWidget);
  return d->values(d->boxCentreBoxes());
}

QVector<double> qBMCTWidget::boxHalfSizes() const {
  Q_D(const qBMCTWidget);
  return d->values(d->boxHalfBoxes());
}

QVector<double> qBMCTWidget::boxRotation() const {
  Q_D(const qBMCTWidget);
  return d->values(d->boxRotationBoxes());
}

void qBMCTWidget::setBox(const QVector<double>& centre, const QVector<double>& halfSizes,
                         const QVector<double>& rotationDeg) {
  Q_D(qBMCTWidget);
  d->setValues(d->boxCentreBoxes(), centre);
  d->setValues(d->boxHalfBoxes(), halfSizes);
  d->setValues(d->boxRotationBoxes(), rotationDeg);
  d->UseBoxCheckBox->setChecked(true);
}

void qBMCTWidget::setUseBox(bool use) {
  Q_D(qBMCTWidget);
  d->UseBoxCheckBox->setChecked(use);
}

QString qBMCTWidget::excludePointsText() const {
  Q_D(const qBMCTWidget);
  return d->ExcludePointsLineEdit->text();
}

bool qBMCTWidget::excludePoints(QVector<double>& xyz, QString& error) const {
  std::vector<double> points;
  error = QString::fromStdString(
      bm::PanelLogic::ParsePoints(this->excludePointsText().toStdString(), points));
  xyz = QVector<double>(points.begin(), points.end());
  return error.isEmpty();
}

void qBMCTWidget::setUseSeed(bool use) {
  Q_D(qBMCTWidget);
  d->UseSeedCheckBox->setChecked(use);
}

void qBMCTWidget::setSeed(const QVector<double>& point) {
  Q_D(qBMCTWidget);
  d->setValues(d->seedBoxes(), point);
  d->UseSeedCheckBox->setChecked(true);
}

void qBMCTWidget::setExcludePointsText(const QString& text) {
  Q_D(qBMCTWidget);
  d->ExcludePointsLineEdit->setText(text);
}

void qBMCTWidget::addExcludePoint(double x, double y, double z) {
  Q_D(qBMCTWidget);
  QString text = d->ExcludePointsLineEdit->text().trimmed();
  if (!text.isEmpty() && !text.endsWith(';'))
    text += "; ";
  else if (!text.isEmpty())
    text += ' ';
  d->ExcludePointsLineEdit->setText(
      text + QString("%1 %2 %3").arg(x, 0, 'f', 2).arg(y, 0, 'f', 2).arg(z, 0, 'f', 2));
}

void qBMCTWidget::setCTPreview(qint64 boneVoxels, double boneVolumeMm3,
                               const QVector<double>& bounds, const QVector<double>& suggestedEntry,
                               const QString& error) {
  Q_D(qBMCTWidget);
  if (!error.isEmpty() || bounds.size() < 6 || suggestedEntry.size() < 3) {
    d->SuggestedEntry.clear();
    d->UseSuggestedEntryButton->setEnabled(false);
    d->CTSummaryLabel->setText(tr("No CT bone: %1").arg(error));
    return;
  }
  d->SuggestedEntry = suggestedEntry;
  d->UseSuggestedEntryButton->setEnabled(true);
  d->CTSummaryLabel->setText(
      tr("Bone: %1 voxels, %2 mm^3 in [%3, %4] x [%5, %6] x [%7, %8] mm; suggested entry "
         "(%9, %10, %11) mm")
          .arg(boneVoxels)
          .arg(boneVolumeMm3, 0, 'f', 1)
          .arg(bounds[0], 0, 'f', 1)
          .arg(bounds[1], 0, 'f', 1)
          .arg(bounds[2], 0, 'f', 1)
          .arg(bounds[3], 0, 'f', 1)
          .arg(bounds[4], 0, 'f', 1)
          .arg(bounds[5], 0, 'f', 1)
          .arg(suggestedEntry[0], 0, 'f', 2)
          .arg(suggestedEntry[1], 0, 'f', 2)
          .arg(suggestedEntry[2], 0, 'f', 2));
}
