// qBMPanel.h - the BoneMachining module panel: choose a tool and its parameters and add it to the
// scene; run a machining session (scene, resolutions with their expected cost, force model,
// tool, device, start / pause / stop, save and reload the cut bone, volume rendering) and follow
// its numbers and live charts.
//
// Shows the tool choice (type, display resolution, every parameter of the tool model) and what
// the logic says about the chosen tool (lips, outer radius, axial length, or why its parameters
// are invalid). It computes nothing: the tool's parameters and their validation come from
// vtkBMToolSource, the expected frame time and force error of a resolution from
// bm::BenchmarkTable (the measured Resources/Benchmark/bench.csv), the scene's own resolutions
// and method from bm::Scene, whether a Touch can be used from vtkBMSessionSource::ProbeTouch().
// Adding the tool and running sessions are left to whoever listens to the requests (the ParaView
// dock creates pipeline sources, vtkBMSessionSource for a session, and feeds the session's numbers
// and history back through setSessionNumbers() and setHistory()).
#pragma once

#include <QScopedPointer>
#include <QString>
#include <QVector>
#include <QWidget>

class qBMPanelPrivate;
class vtkTable;

class qBMPanel : public QWidget {
  Q_OBJECT
  Q_PROPERTY(int toolType READ toolType WRITE setToolType NOTIFY toolTypeChanged)
  Q_PROPERTY(int resolution READ resolution WRITE setResolution)

public:
  using Superclass = QWidget;
  /// A panel showing the default tool (the twist drill) at 64 facets.
  explicit qBMPanel(QWidget* parent = nullptr);
  ~qBMPanel() override;

  /// Chosen tool type, a vtkBMToolSource::ToolTypes value (0 drill, 1 reamer, 2 burr). Default 0.
  int toolType() const;
  /// Chosen number of facets around the tool axis for display. Default 64, range [3, 1024].
  int resolution() const;
  /// One line describing the chosen tool (lips, outer radius in mm, axial length in mm), or why
  /// its parameters are invalid.
  QString toolSummary() const;
  /// The status line set by setStatusMessage(); empty by default.
  QString statusMessage() const;
  /// Session scene: a built-in name or a scene file path. Default "glenoid".
  QString sceneName() const;
  /// Voxmap and shell resolutions for the session (cells along the longest side; 0 = the scene's).
  int voxmapResolution() const;
  int shellResolution() const;
  /// Session device, a vtkBMSessionSource::DeviceTypes value (0 scripted, 1 mouse proxy,
  /// 2 Touch). Default 0.
  int deviceType() const;
  /// The chosen tool's whole specification as JSON (type and every parameter; units in the key
  /// names), as vtkBMToolSource::GetToolSpecification() gives it; "" when the parameters are
  /// invalid.
  QString toolSpecification() const;
  /// Whether the session machines with the tool chosen here (true) or the scene's (default).
  bool useChosenTool() const;
  /// Session force model, a vtkBMSessionSource::MethodTypes value (0 the scene's, 1 Lazar,
  /// 2 Zheng). Default 0.
  int method() const;
  /// The bone file (.nrrd or .mha) to save the cut bone to and to start from. Default "".
  QString boneFile() const;
  /// `path` with a voxmap extension: a name without any extension gets "." + defaultSuffix; one
  /// with an extension ("" too) is returned unchanged (the save refuses formats other than .nrrd
  /// and .mha, naming them). Save uses it, so a name typed or picked without one still saves.
  static QString withVoxmapExtension(const QString& path, const QString& defaultSuffix = "nrrd");
  /// A tool parameter's label for a key of the tool specification: words and the unit, e.g.
  /// "arc_centre_offset_mm" -> "Arc centre offset (mm)", "lips" -> "Lips".
  static QString parameterLabel(const QString& key);
  /// What a tool parameter is, for its tooltip (one per parameter; the label for unknown keys).
  static QString parameterToolTip(const QString& key);
  /// Whether a session starts on the bone file's bone instead of the scene's. Default false.
  bool startFromBoneFile() const;
  /// Whether the cut bone is shown with volume rendering. Default false.
  bool volumeRendering() const;
  /// The expected cost line (frame time in ms, force error in %) of the chosen resolutions.
  QString expectedCost() const;
  /// Why a Touch cannot be used ("" when it can), as probed when the panel was made.
  QString touchStatus() const;
  /// CT bone: the DICOM folder or CT file (""), the bone threshold (HU, default 200), the region
  /// of interest (x0, y0, z0, x1, y1, z1 mm; all zero, the default: none), the preview's voxmap
  /// cells along the region's longest side (default 96).
  QString ctFileName() const;
  double thresholdHU() const;
  QVector<double> roi() const;
  int ctResolution() const;
  /// Tool axis (world, from the bone out; default 0, 0, 1) and entry point (mm, default 0, 0, 0)
  /// for a session on the CT bone.
  QVector<double> axis() const;
  QVector<double> entry() const;
  /// Whether a session machines the CT bone (at entry() along axis()). Default false.
  bool useCTBone() const;
  /// Mouse proxy depth below the entry point, mm. Default -2.
  double toolDepth() const;

public Q_SLOTS:
  /// Choose the tool type (vtkBMToolSource::ToolTypes); out-of-range values are ignored. The
  /// parameter editors are rebuilt at the new type's defaults.
  void setToolType(int type);
  /// Choose the display resolution (facets around the axis); clamped to [3, 1024].
  void setResolution(int facets);
  /// Show a one-line status under the tool controls, e.g. what the last action did; "" clears it.
  void setStatusMessage(const QString& message);
  /// Choose the session's resolutions (0 = the scene's) and device.
  void setVoxmapResolution(int cells);
  void setShellResolution(int cells);
  void setDeviceType(int type);
  /// Choose the session's force model (vtkBMSessionSource::MethodTypes); others are ignored.
  void setMethod(int method);
  /// Use the tool chosen here for the session (true) or the scene's (false).
  void setUseChosenTool(bool use);
  /// Set one parameter of the chosen tool (a key of its specification, e.g. "radius_mm"; the
  /// unit is in the name). Returns false when the tool has no such parameter. The logic validates
  /// the value; toolSummary() then says what is wrong.
  bool setToolParameter(const QString& key, double value);
  /// Set the bone file path (.nrrd or .mha).
  void setBoneFile(const QString& path);
  /// Start sessions from the bone file (true) or the scene's bone (false, the default).
  void setStartFromBoneFile(bool start);
  /// Show the cut bone with volume rendering (true) or as its surface (false, the default).
  void setVolumeRendering(bool on);
  /// Show the session's recent history in the charts: a table with the columns time_s, thrust_N,
  /// torque_Nmm and frame_ms (vtkBMSessionSource's output port 2). The panel keeps a copy; null
  /// clears the charts.
  void setHistory(vtkTable* history);
  /// CT settings (see ctFileName() and the others).
  void setCTFileName(const QString& path);
  void setThresholdHU(double hu);
  void setRoi(const QVector<double>& box);
  void setAxis(const QVector<double>& axis);
  void setEntry(const QVector<double>& entry);
  void setUseCTBone(bool use);
  /// Show the CT preview's result: voxels holding bone, bone volume (mm^3), the voxmap's bounds
  /// (x0, x1, y0, y1, z0, z1 mm) and the suggested entry point (mm), or why it failed (error
  /// not empty: the other values are ignored).
  void setCTPreview(qint64 boneVoxels, double boneVolumeMm3, const QVector<double>& bounds,
                    const QVector<double>& suggestedEntry, const QString& error);
  /// Show the running session's numbers: time (s), depth (mm), removed volume (mm^3), thrust (N),
  /// torque (N mm), frame time p99 (ms).
  void setSessionNumbers(double timeS, double depthMm, double removedMm3, double thrustN,
                         double torqueNmm, double frameP99Ms);
  /// Show the session's state as the logic names it, e.g. "running" or "paused: overrun" (""
  /// clears it). A state beginning with "paused" checks the Pause button and labels it Resume;
  /// "running", "stopped" or "" show Pause.
  void setSessionState(const QString& state);
  /// Show a one-line session status, and whether a session is running (enables the buttons).
  void setSessionStatus(const QString& message, bool running);

Q_SIGNALS:
  /// The tool type changed (vtkBMToolSource::ToolTypes value).
  void toolTypeChanged(int type);
  /// The user asked to add the chosen tool to the scene.
  void addToolRequested(int toolType, int resolution);
  /// The user asked to start a session with the chosen scene, resolutions and device.
  void startSessionRequested(const QString& scene, int voxmapResolution, int shellResolution,
                             int deviceType);
  /// The user asked to pause (true) or resume (false) the session.
  void pauseSessionRequested(bool paused);
  /// The user asked to stop the session.
  void stopSessionRequested();
  /// The mouse proxy's depth changed, mm.
  void toolDepthChanged(double depthMm);
  /// The user asked to save the session's cut bone to `path` (.nrrd or .mha).
  void saveBoneRequested(const QString& path);
  /// The user switched the volume rendering of the cut bone on or off.
  void volumeRenderingToggled(bool on);
  /// The user asked to import and show the CT bone with the panel's CT settings.
  void previewCTRequested();

protected:
  QScopedPointer<qBMPanelPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPanel);
  Q_DISABLE_COPY(qBMPanel);
};
