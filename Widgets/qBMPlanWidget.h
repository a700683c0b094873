// qBMPlanWidget.h - the module panel's Planning section (Docs/Plugin.md, "Planning"): the
// glenoid's landmarks (detected, or placed by hand: a Use box and x, y, z in world mm per
// landmark, what dragging its handle in the 3D view sets) and the face normal, the target
// version and inclination,
// the reaming depth and reamer diameter; the measured angles and sizes, the proposed axis and the
// plan's warnings or why planning failed (implausible results flagged before the steps run);
// placing the glenoid by clicks in the 3D view (Click the face, Click the rim); the plan's view
// and slices; writing the plan's report; buttons that run the guide-pin and the reaming steps.
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
  bool implausible = false; ///< version or inclination beyond +-30 deg, or correction > 15 deg
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
  /// Placing the glenoid by clicking in the 3D view, for when detection fails: 0 off, 1 "Click
  /// the face" (the next click on the bone is a point on the glenoid face; the glenoid is traced
  /// around it), 2 "Click the rim" (each click adds a point on the glenoid's rim; three or more
  /// give the glenoid). Default 0.
  int placementMode() const;
  /// The point clicked on the face (world mm), when one is in use.
  bool useFacePoint() const;
  QVector<double> facePoint() const;
  /// The points clicked on the rim (world mm, 3 per point).
  QVector<double> rimPoints() const;
  /// The folder "Write report" writes into (default empty: none chosen).
  QString reportFolder() const;
  /// Whether "Write result" also writes the result as DICOM beside the plan's CT (a DICOM
  /// series; the filter's ResultAsDicom). Default off.
  bool resultAsDicom() const;

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
  /// Sets the placement mode (see placementMode()); emits placementModeChanged().
  void setPlacementMode(int mode);
  /// A point clicked on the bone in the 3D view (world mm) in the current placement mode: "Click
  /// the face" takes it as the face point, ends the mode and emits planRequested(); "Click the
  /// rim" adds it and, from the third point on, emits planRequested(). Ignored with the mode off.
  void addPlacedPoint(const QVector<double>& point);
  /// Forgets the face point and the rim points (the glenoid is detected again); emits
  /// planRequested().
  void clearPlacedPoints();
  void setReportFolder(const QString& folder);
  /// Shows what writing the report did (the folder and files, or why it failed).
  void setReportStatus(const QString& text, bool ok);

Q_SIGNALS:
  /// Plan (again) with the section's settings: Plan pressed, a landmark or target changed.
  void planRequested();
  /// Run step `step` of the plan (0 the guide-pin hole, 1 the reaming) in a session.
  void runStepRequested(int step);
  /// The placement mode changed (0 off, 1 face, 2 rim): clicks in the 3D view are to be sent to
  /// addPlacedPoint() while it is not 0.
  void placementModeChanged(int mode);
  /// Point the 3D view's camera as the plan's pictures do (down the planned axis).
  void viewPlanRequested();
  /// Show a slice through the plan: 0 axial at the glenoid centre, 1 along the planned axis
  /// (containing the axis and the superior direction).
  void sliceRequested(int kind);
  /// Write the plan's files and report into reportFolder(), as bmsim plan writes them.
  void writeReportRequested();
  /// Write the result of the plan's steps as run (the outcome on the bone, the pictures before
  /// and after, plan_result.md/.html) into reportFolder(), as bmsim run writes a plan's.
  void writeResultRequested();

protected:
  QScopedPointer<qBMPlanWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPlanWidget);
  Q_DISABLE_COPY(qBMPlanWidget);
};
