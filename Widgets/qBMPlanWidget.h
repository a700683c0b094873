// qBMPlanWidget.h - the module panel's Planning section (Docs/Plugin.md, "Planning"): the
// glenoid's landmarks (detected, or placed by hand: a Use box and x, y, z in world mm per
// landmark, what dragging its handle in the 3D view sets) and the face normal, the target
// version and inclination,
// the reaming depth and reamer diameter; the measured angles and sizes, the proposed axis and the
// plan's warnings or why planning failed; buttons that run the guide-pin and the reaming steps.
//
// Computes nothing: the plan is made by the BM Glenoid Plan filter (vtkBMGlenoidPlanFilter) that
// whoever listens to planRequested() updates; its result comes back through setPlanResult() or
// setPlanFailure(). Object names (PlanGroupBox, UseTrigonumCheckBox, TrigonumXSpinBox,
// FriedmanVersionLabel, RunPinButton, ...) address it from the GUI tests.
#pragma once

#include <QGroupBox>
#include <QScopedPointer>
#include <QString>
#include <QStringList>
#include <QVector>

class qBMPlanWidgetPrivate;

/// What the panel shows of a plan (angles deg, lengths mm, points world mm).
struct qBMPlanResult {
  double friedmanVersionDeg = 0, version3DDeg = 0, inclinationDeg = 0;
  double heightMm = 0, widthMm = 0, faceRadiusMm = 0;
  double correctionDeg = 0;
  bool reamerFits = false;
  QVector<double> glenoidCentre, trigonum, inferiorAngle; ///< the landmarks used, 3 each
  QVector<double> faceNormal;                             ///< the face normal used (unit)
  QVector<double> entry, axis;                            ///< the planned axis (unit), 3 each
  QStringList warnings;
  bool canRunSteps = false; ///< a plan scene exists (the CT is known)
};

class qBMPlanWidget : public QGroupBox {
  Q_OBJECT

public:
  using Superclass = QGroupBox;
  explicit qBMPlanWidget(QWidget* parent = nullptr);
  ~qBMPlanWidget() override;

  /// Landmark `i` (0 glenoid centre, 1 trigonum, 2 inferior angle, 3 face normal): whether the
  /// value given in the section replaces the detected one (default false) and that value: a
  /// point (world mm, default 0, 0, 0; each coordinate in [-10000, 10000]) or, for the face
  /// normal, a direction out of the joint (default 1, 0, 0; components in [-1, 1]).
  bool useLandmark(int i) const;
  QVector<double> landmark(int i) const;
  /// Target version and inclination of the reaming axis, deg (default 0, range [-44.9, 44.9]).
  double targetVersion() const;
  double targetInclination() const;
  /// Reaming depth below the glenoid centre, mm (default 2, range [0.01, 10]).
  double reamDepth() const;
  /// Reamer diameter, mm (default 36.5, range [10.01, 60]).
  double reamerDiameter() const;
  /// The text of the measured angles' labels (for tests and the status line).
  QString measurementsText() const;

public Q_SLOTS:
  /// Sets landmark `i` (world mm) and uses it (the 3D view's handle was dragged); emits
  /// planRequested().
  void setLandmark(int i, const QVector<double>& point);
  void setUseLandmark(int i, bool use);
  void setTargets(double versionDeg, double inclinationDeg);
  /// Shows a plan's measurements and axis; the landmarks not in use take the plan's (detected)
  /// points, so that the handles start where detection put them.
  void setPlanResult(const qBMPlanResult& result);
  /// Shows why planning failed (e.g. "no glenoid found: ... place landmarks") and disables the
  /// step buttons.
  void setPlanFailure(const QString& error);

Q_SIGNALS:
  /// Plan (again) with the section's settings: Plan pressed, a landmark or target changed.
  void planRequested();
  /// Run step `step` of the plan (0 the guide-pin hole, 1 the reaming) in a session.
  void runStepRequested(int step);

protected:
  QScopedPointer<qBMPlanWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPlanWidget);
  Q_DISABLE_COPY(qBMPlanWidget);
};
