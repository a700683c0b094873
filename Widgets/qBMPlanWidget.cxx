// qBMPlanWidget.cxx - see qBMPlanWidget.h.
#include "qBMPlanWidget.h"

#include <cmath>

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QFileDialog>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalBlocker>
#include <QVBoxLayout>

#include <array>
#include <cmath>

namespace {
constexpr int kLandmarks = 4; ///< glenoid centre, trigonum, inferior angle, face normal
const char* const kLandmarkNames[kLandmarks] = {"GlenoidCentre", "Trigonum", "InferiorAngle",
                                                "FaceNormal"};
const char* const kLandmarkLabels[kLandmarks] = {"Glenoid centre", "Trigonum", "Inferior angle",
                                                 "Face normal"};
} // namespace

class qBMPlanWidgetPrivate {
  Q_DECLARE_PUBLIC(qBMPlanWidget);

public:
  explicit qBMPlanWidgetPrivate(qBMPlanWidget& object) : q_ptr(&object) {}
  void init();
  /// A spin box that plans again when edited; for landmark `landmark` (>= 0), an edit also
  /// turns on the landmark's Use box (a typed value is meant to be used, and a plan would
  /// otherwise replace it with the detected one).
  QDoubleSpinBox* spinBox(const QString& name, double lo, double hi, double value,
                          const QString& suffix, const QString& tip, int landmark = -1);

  qBMPlanWidget* const q_ptr;
  std::array<QCheckBox*, kLandmarks> Use{};
  std::array<std::array<QDoubleSpinBox*, 3>, kLandmarks> Point{};
  QDoubleSpinBox* TargetVersion = nullptr;
  QDoubleSpinBox* TargetInclination = nullptr;
  QDoubleSpinBox* ReamDepth = nullptr;
  QDoubleSpinBox* ReamerDiameter = nullptr;
  QLabel* FriedmanVersion = nullptr;
  QLabel* Version3D = nullptr;
  QLabel* Inclination = nullptr;
  QLabel* Size = nullptr;
  QLabel* Axis = nullptr;
  QLabel* Status = nullptr;
  QPushButton* Plan = nullptr;
  QPushButton* RunPin = nullptr;
  QPushButton* RunReam = nullptr;
  QPushButton* PlaceFace = nullptr;
  QPushButton* PlaceRim = nullptr;
  QPushButton* ClearPlaced = nullptr;
  QLabel* Placed = nullptr;
  QLineEdit* ReportFolder = nullptr;
  QCheckBox* ResultAsDicom = nullptr;
  QLabel* ReportStatus = nullptr;
  int Mode = 0;
  bool HaveFacePoint = false;
  QVector<double> FacePoint{0, 0, 0};
  QVector<double> RimPoints;
  void showPlaced();
  /// A push button named `name` (for the GUI tests), with its tooltip; checkable when asked.
  QPushButton* button(const QString& text, const char* name, const QString& tip,
                      bool checkable = false) {
    auto* b = new QPushButton(text, this->q_ptr);
    b->setObjectName(name);
    b->setToolTip(tip);
    b->setCheckable(checkable);
    return b;
  }
  /// A glenoid placed by clicks replaces a typed centre and normal: their Use boxes go off.
  void unuseTypedGlenoid() {
    for (int i : {0, 3}) {
      const QSignalBlocker block(this->Use[size_t(i)]);
      this->Use[size_t(i)]->setChecked(false);
    }
  }
};

void qBMPlanWidgetPrivate::showPlaced() {
  const int rim = this->RimPoints.size() / 3;
  QString text;
  if (this->Mode == 1)
    text = qBMPlanWidget::tr("Click on the glenoid face in the 3D view.");
  else if (this->Mode == 2)
    text = qBMPlanWidget::tr("Click points on the glenoid's rim in the 3D view: %1 placed%2.")
               .arg(rim)
               .arg(rim < 3 ? qBMPlanWidget::tr(" (three or more needed)") : QString());
  else if (this->HaveFacePoint)
    text = qBMPlanWidget::tr("Placed: a point on the face at (%1, %2, %3) mm.")
               .arg(this->FacePoint[0], 0, 'f', 1)
               .arg(this->FacePoint[1], 0, 'f', 1)
               .arg(this->FacePoint[2], 0, 'f', 1);
  else if (rim >= 3)
    text = qBMPlanWidget::tr("Placed: %1 points on the rim.").arg(rim);
  else
    text = qBMPlanWidget::tr("Detected (nothing placed).");
  this->Placed->setText(text);
  const QSignalBlocker b0(this->PlaceFace), b1(this->PlaceRim);
  this->PlaceFace->setChecked(this->Mode == 1);
  this->PlaceRim->setChecked(this->Mode == 2);
  this->ClearPlaced->setEnabled(this->HaveFacePoint || !this->RimPoints.isEmpty());
}

QDoubleSpinBox* qBMPlanWidgetPrivate::spinBox(const QString& name, double lo, double hi,
                                              double value, const QString& suffix,
                                              const QString& tip, int landmark) {
  Q_Q(qBMPlanWidget);
  auto* box = new QDoubleSpinBox(q);
  box->setObjectName(name);
  box->setRange(lo, hi);
  box->setDecimals(2);
  box->setValue(value);
  box->setSuffix(suffix);
  box->setToolTip(tip);
  box->setKeyboardTracking(false); // one plan per edit, not per keystroke
  QObject::connect(box, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q,
                   [this, q, landmark](double) {
                     if (landmark >= 0 && this->Use[size_t(landmark)]) {
                       const QSignalBlocker block(this->Use[size_t(landmark)]);
                       this->Use[size_t(landmark)]->setChecked(true);
                     }
                     Q_EMIT q->planRequested();
                   });
  return box;
}

void qBMPlanWidgetPrivate::init() {
  Q_Q(qBMPlanWidget);
  q->setObjectName("PlanGroupBox");
  q->setTitle(qBMPlanWidget::tr("Planning"));
  auto* layout = new QVBoxLayout(q);
  auto* marks = new QGridLayout;
  for (int i = 0; i < kLandmarks; ++i) {
    const QString name = kLandmarkNames[i];
    this->Use[i] = new QCheckBox(qBMPlanWidget::tr(kLandmarkLabels[i]), q);
    this->Use[i]->setObjectName("Use" + name + "CheckBox");
    const bool direction = i == 3;
    this->Use[i]->setToolTip(
        direction ? qBMPlanWidget::tr("Use the direction given here (out of the joint, "
                                      "normalised) instead of the detected face normal; with a "
                                      "given glenoid centre the joint is not searched for")
                  : qBMPlanWidget::tr("Use the point given here (world mm) instead of the "
                                      "detected one; dragging the landmark's handle in the 3D "
                                      "view sets it"));
    QObject::connect(this->Use[i], &QCheckBox::toggled, q,
                     [q](bool) { Q_EMIT q->planRequested(); });
    marks->addWidget(this->Use[i], i, 0);
    for (int c = 0; c < 3; ++c) {
      const QString box = name + QStringList{"X", "Y", "Z"}[c] + "SpinBox";
      this->Point[i][c] = direction
                              ? this->spinBox(box, -1, 1, c == 0 ? 1 : 0, "",
                                              qBMPlanWidget::tr("Direction component (world)"), i)
                              : this->spinBox(box, -10000, 10000, 0, " mm",
                                              qBMPlanWidget::tr("World coordinate, mm"), i);
      if (direction)
        this->Point[i][c]->setDecimals(4);
      marks->addWidget(this->Point[i][c], i, c + 1);
    }
  }
  layout->addLayout(marks);
  auto* form = new QFormLayout;
  this->TargetVersion =
      this->spinBox("TargetVersionSpinBox", -44.9, 44.9, 0, " deg",
                    qBMPlanWidget::tr("Target version of the reaming axis (negative = "
                                      "retroversion)"));
  this->TargetInclination =
      this->spinBox("TargetInclinationSpinBox", -44.9, 44.9, 0, " deg",
                    qBMPlanWidget::tr("Target inclination (positive = superior)"));
  this->ReamDepth = this->spinBox("ReamDepthSpinBox", 0.01, 10, 2, " mm",
                                  qBMPlanWidget::tr("Reaming depth below the glenoid centre"));
  this->ReamerDiameter =
      this->spinBox("ReamerDiameterSpinBox", 10.01, 60, 36.5, " mm",
                    qBMPlanWidget::tr("Reamer diameter, checked against the glenoid"));
  form->addRow(qBMPlanWidget::tr("Target version"), this->TargetVersion);
  form->addRow(qBMPlanWidget::tr("Target inclination"), this->TargetInclination);
  form->addRow(qBMPlanWidget::tr("Reaming depth"), this->ReamDepth);
  form->addRow(qBMPlanWidget::tr("Reamer diameter"), this->ReamerDiameter);
  auto label = [q](const char* name) {
    auto* l = new QLabel(qBMPlanWidget::tr("-"), q);
    l->setObjectName(name);
    l->setWordWrap(true);
    l->setTextInteractionFlags(Qt::TextSelectableByMouse);
    return l;
  };
  this->FriedmanVersion = label("FriedmanVersionLabel");
  this->Version3D = label("Version3DLabel");
  this->Inclination = label("InclinationLabel");
  this->Size = label("GlenoidSizeLabel");
  this->Axis = label("PlanAxisLabel");
  this->Status = label("PlanStatusLabel");
  form->addRow(qBMPlanWidget::tr("Version (Friedman 2D)"), this->FriedmanVersion);
  form->addRow(qBMPlanWidget::tr("Version (3D)"), this->Version3D);
  form->addRow(qBMPlanWidget::tr("Inclination (3D)"), this->Inclination);
  form->addRow(qBMPlanWidget::tr("Glenoid"), this->Size);
  form->addRow(qBMPlanWidget::tr("Reaming axis"), this->Axis);
  layout->addLayout(form);
  layout->addWidget(this->Status);
  auto* buttons = new QHBoxLayout;
  this->Plan = new QPushButton(qBMPlanWidget::tr("Plan"), q);
  this->Plan->setObjectName("PlanButton");
  this->RunPin = new QPushButton(qBMPlanWidget::tr("Run guide pin"), q);
  this->RunPin->setObjectName("RunPinButton");
  this->RunReam = new QPushButton(qBMPlanWidget::tr("Run reaming"), q);
  this->RunReam->setObjectName("RunReamButton");
  this->RunPin->setEnabled(false);
  this->RunReam->setEnabled(false);
  QObject::connect(this->Plan, &QPushButton::clicked, q, &qBMPlanWidget::planRequested);
  QObject::connect(this->RunPin, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->runStepRequested(0); });
  QObject::connect(this->RunReam, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->runStepRequested(1); });
  buttons->addWidget(this->Plan);
  buttons->addWidget(this->RunPin);
  buttons->addWidget(this->RunReam);

  // Placing the glenoid in the 3D view.
  auto* place = new QHBoxLayout;
  this->PlaceFace = this->button(
      qBMPlanWidget::tr("Click the face"), "PlaceFaceButton",
      qBMPlanWidget::tr(
          "Then click on the glenoid face in the 3D view: the glenoid is traced around that point "
          "(for when it is not found: no humeral head in the scan, or one fused to the glenoid)"),
      true);
  this->PlaceRim = this->button(
      qBMPlanWidget::tr("Click the rim"), "PlaceRimButton",
      qBMPlanWidget::tr("Then click three or more points around the glenoid's rim in the 3D view: "
                        "their plane gives the glenoid's centre and face normal"),
      true);
  this->ClearPlaced = this->button(qBMPlanWidget::tr("Clear placed"), "ClearPlacedButton",
                                   qBMPlanWidget::tr("Forget the clicked points: detect again"));
  QObject::connect(this->PlaceFace, &QPushButton::toggled, q,
                   [q](bool on) { q->setPlacementMode(on ? 1 : 0); });
  QObject::connect(this->PlaceRim, &QPushButton::toggled, q,
                   [q](bool on) { q->setPlacementMode(on ? 2 : 0); });
  QObject::connect(this->ClearPlaced, &QPushButton::clicked, q, &qBMPlanWidget::clearPlacedPoints);
  place->addWidget(this->PlaceFace);
  place->addWidget(this->PlaceRim);
  place->addWidget(this->ClearPlaced);
  this->Placed = label("PlacedLabel");
  layout->insertLayout(1, place);
  layout->insertWidget(2, this->Placed);

  // Seeing the plan: its view and slices.
  auto* see = new QHBoxLayout;
  auto* view =
      this->button(qBMPlanWidget::tr("View plan"), "ViewPlanButton",
                   qBMPlanWidget::tr("Look down the planned axis, as the report's pictures do"));
  auto* axial =
      this->button(qBMPlanWidget::tr("Axial slice"), "AxialSliceButton",
                   qBMPlanWidget::tr("The CT on the axial plane through the glenoid centre"));
  auto* along = this->button(
      qBMPlanWidget::tr("Slice along axis"), "AxisSliceButton",
      qBMPlanWidget::tr("The CT on the plane holding the planned axis and the superior direction"));
  QObject::connect(view, &QPushButton::clicked, q, &qBMPlanWidget::viewPlanRequested);
  QObject::connect(axial, &QPushButton::clicked, q, [q]() { Q_EMIT q->sliceRequested(0); });
  QObject::connect(along, &QPushButton::clicked, q, [q]() { Q_EMIT q->sliceRequested(1); });
  see->addWidget(view);
  see->addWidget(axial);
  see->addWidget(along);
  layout->addLayout(see);
  layout->addLayout(buttons);

  // The report, as bmsim plan writes it.
  auto* report = new QHBoxLayout;
  this->ReportFolder = new QLineEdit(q);
  this->ReportFolder->setObjectName("ReportFolderLineEdit");
  this->ReportFolder->setPlaceholderText(qBMPlanWidget::tr("folder for the plan's report"));
  auto* browse = this->button(qBMPlanWidget::tr("..."), "ReportFolderBrowseButton",
                              qBMPlanWidget::tr("Choose the report's folder"));
  QObject::connect(browse, &QPushButton::clicked, q, [this, q]() {
    const QString dir = QFileDialog::getExistingDirectory(
        q, qBMPlanWidget::tr("Folder for the plan's report"), this->ReportFolder->text());
    if (!dir.isEmpty())
      this->ReportFolder->setText(dir);
  });
  auto* write = this->button(
      qBMPlanWidget::tr("Write report"), "WriteReportButton",
      qBMPlanWidget::tr("plan.json, the step scenes and plan_report.md/.html/.json, as bmsim plan "
                        "writes them"));
  QObject::connect(write, &QPushButton::clicked, q, &qBMPlanWidget::writeReportRequested);
  auto* result = this->button(
      qBMPlanWidget::tr("Write result"), "WriteResultButton",
      qBMPlanWidget::tr(
          "After the plan's reaming: the outcome on the bone (removed bone, the reamed face "
          "against the plan, seating), the glenoid before and after, plan_result.md/.html, as "
          "bmsim run writes a plan's result"));
  QObject::connect(result, &QPushButton::clicked, q, &qBMPlanWidget::writeResultRequested);
  this->ResultAsDicom = new QCheckBox(qBMPlanWidget::tr("DICOM"), q);
  this->ResultAsDicom->setObjectName("ResultAsDicomCheckBox");
  this->ResultAsDicom->setToolTip(qBMPlanWidget::tr(
      "Write result also writes dicom/reamed-bone.seg.dcm (the bone removed and remaining, a "
      "Segmentation) and dicom/plan.sr.dcm (the measurements, a Structured Report) in the CT's "
      "study, for a CT read from a DICOM series"));
  report->addWidget(this->ReportFolder, 1);
  report->addWidget(browse);
  report->addWidget(write);
  report->addWidget(result);
  report->addWidget(this->ResultAsDicom);
  layout->addLayout(report);
  this->ReportStatus = label("ReportStatusLabel");
  this->ReportStatus->setText(QString());
  layout->addWidget(this->ReportStatus);
  this->showPlaced();
}

qBMPlanWidget::qBMPlanWidget(QWidget* parent)
    : Superclass(parent), d_ptr(new qBMPlanWidgetPrivate(*this)) {
  Q_D(qBMPlanWidget);
  d->init();
}

qBMPlanWidget::~qBMPlanWidget() = default;

bool qBMPlanWidget::useLandmark(int i) const {
  Q_D(const qBMPlanWidget);
  return i >= 0 && i < kLandmarks && d->Use[i]->isChecked();
}

QVector<double> qBMPlanWidget::landmark(int i) const {
  Q_D(const qBMPlanWidget);
  if (i < 0 || i >= kLandmarks)
    return {};
  return {d->Point[i][0]->value(), d->Point[i][1]->value(), d->Point[i][2]->value()};
}

double qBMPlanWidget::targetVersion() const {
  Q_D(const qBMPlanWidget);
  return d->TargetVersion->value();
}

double qBMPlanWidget::targetInclination() const {
  Q_D(const qBMPlanWidget);
  return d->TargetInclination->value();
}

double qBMPlanWidget::reamDepth() const {
  Q_D(const qBMPlanWidget);
  return d->ReamDepth->value();
}

double qBMPlanWidget::reamerDiameter() const {
  Q_D(const qBMPlanWidget);
  return d->ReamerDiameter->value();
}

QString qBMPlanWidget::measurementsText() const {
  Q_D(const qBMPlanWidget);
  return tr("Friedman %1; 3D %2; inclination %3")
      .arg(d->FriedmanVersion->text(), d->Version3D->text(), d->Inclination->text());
}

void qBMPlanWidget::setLandmark(int i, const QVector<double>& point) {
  Q_D(qBMPlanWidget);
  if (i < 0 || i >= kLandmarks || point.size() < 3)
    return;
  {
    const QSignalBlocker b0(d->Point[i][0]), b1(d->Point[i][1]), b2(d->Point[i][2]), b3(d->Use[i]);
    for (int c = 0; c < 3; ++c)
      d->Point[i][c]->setValue(point[c]);
    d->Use[i]->setChecked(true);
  }
  Q_EMIT this->planRequested();
}

void qBMPlanWidget::setUseLandmark(int i, bool use) {
  Q_D(qBMPlanWidget);
  if (i >= 0 && i < kLandmarks)
    d->Use[i]->setChecked(use);
}

void qBMPlanWidget::setTargets(double versionDeg, double inclinationDeg) {
  Q_D(qBMPlanWidget);
  {
    const QSignalBlocker b0(d->TargetVersion), b1(d->TargetInclination);
    d->TargetVersion->setValue(versionDeg);
    d->TargetInclination->setValue(inclinationDeg);
  }
  Q_EMIT this->planRequested();
}

void qBMPlanWidget::setPlanResult(const qBMPlanResult& r) {
  Q_D(qBMPlanWidget);
  // A measurement the landmarks do not allow (NaN) reads "not available"; the warnings say why.
  auto num = [](double v, const char* unit) {
    return std::isfinite(v) ? qBMPlanWidget::tr("%1 %2").arg(v, 0, 'f', 1).arg(unit)
                            : qBMPlanWidget::tr("not available");
  };
  d->FriedmanVersion->setText(num(r.friedmanVersionDeg, "deg"));
  d->Version3D->setText(num(r.version3DDeg, "deg"));
  d->Inclination->setText(num(r.inclinationDeg, "deg"));
  d->Size->setText(
      tr("%1 x %2, radius of curvature %3")
          .arg(num(r.heightMm, "mm"), num(r.widthMm, "mm"), num(r.faceRadiusMm, "mm")));
  if (r.entry.size() >= 3 && r.axis.size() >= 3)
    d->Axis->setText(tr("from (%1, %2, %3) mm along (%4, %5, %6), correction %7 deg")
                         .arg(r.entry[0], 0, 'f', 1)
                         .arg(r.entry[1], 0, 'f', 1)
                         .arg(r.entry[2], 0, 'f', 1)
                         .arg(r.axis[0], 0, 'f', 3)
                         .arg(r.axis[1], 0, 'f', 3)
                         .arg(r.axis[2], 0, 'f', 3)
                         .arg(r.correctionDeg, 0, 'f', 1));
  QStringList status;
  status << (r.reamerFits               ? tr("The reamer fits the glenoid.")
             : std::isfinite(r.widthMm) ? tr("The reamer overhangs the glenoid.")
                                        : tr("The reamer's size is not checked (no rim)."));
  status << r.warnings;
  if (r.implausible)
    status.prepend(tr("CHECK THE PLAN: the measurements are implausible for a glenoid (see the "
                      "warnings); check the landmarks before running the steps."));
  if (!r.canRunSteps)
    status << tr("Name the CT to run the steps.");
  d->Status->setText(status.join("\n"));
  d->Status->setStyleSheet(r.implausible ? "color: #c00000; font-weight: bold" : QString());
  const QVector<double>* used[kLandmarks] = {&r.glenoidCentre, &r.trigonum, &r.inferiorAngle,
                                             &r.faceNormal};
  for (int i = 0; i < kLandmarks; ++i)
    if (!d->Use[i]->isChecked() && used[i]->size() >= 3)
      for (int c = 0; c < 3; ++c) {
        const QSignalBlocker block(d->Point[i][c]);
        d->Point[i][c]->setValue((*used[i])[c]);
      }
  d->RunPin->setEnabled(r.canRunSteps);
  d->RunReam->setEnabled(r.canRunSteps);
}

void qBMPlanWidget::setPlanFailure(const QString& error) {
  Q_D(qBMPlanWidget);
  for (QLabel* l : {d->FriedmanVersion, d->Version3D, d->Inclination, d->Size, d->Axis})
    l->setText(tr("-"));
  d->Status->setText(tr("No plan: %1").arg(error));
  d->Status->setStyleSheet(QString());
  d->RunPin->setEnabled(false);
  d->RunReam->setEnabled(false);
}

int qBMPlanWidget::placementMode() const {
  Q_D(const qBMPlanWidget);
  return d->Mode;
}

bool qBMPlanWidget::useFacePoint() const {
  Q_D(const qBMPlanWidget);
  return d->HaveFacePoint;
}

QVector<double> qBMPlanWidget::facePoint() const {
  Q_D(const qBMPlanWidget);
  return d->FacePoint;
}

QVector<double> qBMPlanWidget::rimPoints() const {
  Q_D(const qBMPlanWidget);
  return d->RimPoints;
}

QString qBMPlanWidget::reportFolder() const {
  Q_D(const qBMPlanWidget);
  return d->ReportFolder->text();
}

bool qBMPlanWidget::resultAsDicom() const {
  Q_D(const qBMPlanWidget);
  return d->ResultAsDicom->isChecked();
}

void qBMPlanWidget::setPlacementMode(int mode) {
  Q_D(qBMPlanWidget);
  mode = mode == 1 || mode == 2 ? mode : 0;
  if (mode == d->Mode)
    return;
  d->Mode = mode;
  if (mode == 2) { // a new set of rim points
    d->RimPoints.clear();
    d->HaveFacePoint = false;
  }
  d->showPlaced();
  Q_EMIT this->placementModeChanged(mode);
}

void qBMPlanWidget::addPlacedPoint(const QVector<double>& point) {
  Q_D(qBMPlanWidget);
  if (point.size() < 3 || d->Mode == 0)
    return;
  if (d->Mode == 1) {
    d->FacePoint = {point[0], point[1], point[2]};
    d->HaveFacePoint = true;
    d->RimPoints.clear();
    d->unuseTypedGlenoid();
    this->setPlacementMode(0);
    Q_EMIT this->planRequested();
    return;
  }
  d->RimPoints << point[0] << point[1] << point[2];
  d->showPlaced();
  if (d->RimPoints.size() >= 9) {
    d->unuseTypedGlenoid();
    Q_EMIT this->planRequested();
  }
}

void qBMPlanWidget::clearPlacedPoints() {
  Q_D(qBMPlanWidget);
  d->HaveFacePoint = false;
  d->RimPoints.clear();
  this->setPlacementMode(0);
  d->showPlaced();
  Q_EMIT this->planRequested();
}

void qBMPlanWidget::setReportFolder(const QString& folder) {
  Q_D(qBMPlanWidget);
  d->ReportFolder->setText(folder);
}

void qBMPlanWidget::setReportStatus(const QString& text, bool ok) {
  Q_D(qBMPlanWidget);
  d->ReportStatus->setText(text);
  d->ReportStatus->setStyleSheet(ok ? QString() : QString("color: #c00000"));
}
