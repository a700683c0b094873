// qBMCTWidget.h - the module panel's CT section: a DICOM folder or CT file, the bone threshold,
// the region of interest and the preview's resolution; the tool axis and entry point for a
// session on the CT bone; the preview's result (bone voxels, volume, bounds, suggested entry) or
// why the import failed.
//
// Computes nothing: the import runs in the BM CT Bone source (vtkBMCTBoneSource) that whoever
// listens to previewCTRequested() updates, and its result comes back through setCTPreview().
// Object names (CTGroupBox, CTFileLineEdit, ThresholdSpinBox, PreviewCTButton, ...) address it
// from the GUI tests. In a build with DCMTK, "From PACS..." (FromPacsButton) opens the PACS
// study browser (qBMPacsBrowser.h): a fetched series becomes the CT as a chosen folder would.
#pragma once

#include <QGroupBox>
#include <QScopedPointer>
#include <QString>
#include <QVector>

class qBMCTWidgetPrivate;
class qBMPacsBrowser;

class qBMCTWidget : public QGroupBox {
  Q_OBJECT

public:
  using Superclass = QGroupBox;
  explicit qBMCTWidget(QWidget* parent = nullptr);
  ~qBMCTWidget() override;

  /// The DICOM folder or CT file. Default "".
  QString ctFileName() const;
  /// The PACS study browser that "From PACS..." opens (a dialog owned by this widget); nullptr
  /// in a build without DCMTK (BM_WITH_DCMTK=OFF), where the button does not exist.
  qBMPacsBrowser* pacsBrowser() const;
  /// The bone threshold: HU, or the file's own units with intensityMode() 1 (raw values).
  /// Default 200, range [-2000, 10000].
  double thresholdHU() const;
  /// How the CT's values are read (vtkBMCTBoneSource::IntensityModes): 0 = HU as the file gives
  /// them (the default), 1 = raw values (thresholdHU() in the file's units), 2 = huMapping().
  int intensityMode() const;
  /// The mapping to HU of mode 2: {slope, intercept (HU)}, HU = slope x value + intercept.
  /// Default {1, -1024}.
  QVector<double> huMapping() const;
  /// The region of interest (x0, y0, z0, x1, y1, z1), mm; all zero (the default): none.
  QVector<double> roi() const;
  /// The preview's voxmap cells along the region's longest side. Default 96, range [8, 1024].
  int ctResolution() const;
  /// Tool axis (world, from the bone out; default 0, 0, 1; each component in [-1, 1]).
  QVector<double> axis() const;
  /// Entry point, mm. Default 0, 0, 0.
  QVector<double> entry() const;
  /// Whether a session machines the CT bone (at entry() along axis()). Default false.
  bool useCTBone() const;
  /// Whether the bone at seed() is kept (else the largest bone). Default false.
  bool useSeed() const;
  /// Whether every bone is kept (the scapula and the humeral head together, for planning), not
  /// only the largest or the seeded one. Default false.
  bool keepAllBones() const;
  /// The include seed, world mm. Default 0, 0, 0.
  QVector<double> seed() const;
  /// The exclude points as typed ("x y z; x y z", world mm). Default "".
  QString excludePointsText() const;
  /// Whether only the bone inside the oriented box is kept. Default false.
  bool useBox() const;
  /// The oriented box: centre (world mm, default 0, 0, 0), half sizes along its own axes (mm,
  /// default 50 each, range (0, 10000]) and rotation (deg about world x, then y, then z; default
  /// 0, range [-360, 360]), as vtkBMCTBoneSource takes them.
  QVector<double> boxCentre() const;
  QVector<double> boxHalfSizes() const;
  QVector<double> boxRotation() const;
  /// The exclude points, x y z per point (world mm), read by bm::PanelLogic::ParsePoints; for
  /// malformed text false, `xyz` empty and `error` naming the point.
  bool excludePoints(QVector<double>& xyz, QString& error) const;

public Q_SLOTS:
  void setCTFileName(const QString& path);
  void setThresholdHU(double hu);
  void setIntensityMode(int mode);
  /// Sets the region of interest (mm); extra values are ignored, missing ones kept.
  void setRoi(const QVector<double>& box);
  void setAxis(const QVector<double>& axis);
  void setEntry(const QVector<double>& entry);
  void setUseCTBone(bool use);
  void setUseSeed(bool use);
  void setKeepAllBones(bool keep);
  /// Sets the include seed (world mm) and keeps the bone there (useSeed() true).
  void setSeed(const QVector<double>& point);
  void setExcludePointsText(const QString& text);
  /// Sets the oriented box (see boxCentre()) and keeps only the bone inside it (useBox() true).
  void setBox(const QVector<double>& centre, const QVector<double>& halfSizes,
              const QVector<double>& rotationDeg);
  void setUseBox(bool use);
  /// Appends one exclude point (world mm) to the list.
  void addExcludePoint(double x, double y, double z);
  /// Show the CT preview's result: voxels holding bone, bone volume (mm^3), the voxmap's bounds
  /// (x0, x1, y0, y1, z0, z1 mm) and the suggested entry point (mm), or why it failed (error
  /// not empty: the other values are ignored). A suggested entry enables "Use suggested entry".
  void setCTPreview(qint64 boneVoxels, double boneVolumeMm3, const QVector<double>& bounds,
                    const QVector<double>& suggestedEntry, const QString& error);

Q_SIGNALS:
  /// The user asked to import and show the CT bone with these settings.
  void previewCTRequested();

protected:
  QScopedPointer<qBMCTWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMCTWidget);
  Q_DISABLE_COPY(qBMCTWidget);
};
