// qBMSessionWidget.h - the module panel's session section: scene, resolutions with their expected
// cost, force model, whether to use the panel's tool, device (the Touch entry enabled once a probe
// off the GUI thread says it is ready), force scale, mouse-proxy depth, bone file (save, start
// from it), volume rendering; Start / Pause-Resume / Stop with the session's state, numbers and a
// busy indicator while a session's bone is built.
//
// Computes nothing: the expected cost, state words, force-scale range and file extension come
// from bm::PanelLogic (bmPanelLogic.h), the Touch probe from qBMTouchProbe. Running a session is
// left to whoever listens to the requests (the ParaView dock). Object names (SessionGroupBox,
// StartButton, PauseButton, ToolDepthSpinBox, ...) address it from the GUI tests.
#pragma once

#include <QGroupBox>
#include <QScopedPointer>
#include <QString>

namespace bm {
enum class SessionState; // bmHapticSession.h
}
class qBMSessionWidgetPrivate;
class qBMTouchProbe;

class qBMSessionWidget : public QGroupBox {
  Q_OBJECT

public:
  using Superclass = QGroupBox;
  /// Starts probing the Touch (qBMTouchProbe, off the GUI thread); until it answers the Touch
  /// entry is disabled and touchStatus() reads "probing".
  explicit qBMSessionWidget(QWidget* parent = nullptr);
  ~qBMSessionWidget() override;

  /// Session scene: a built-in name or a scene file path. Default "glenoid".
  QString sceneName() const;
  /// Voxmap and shell resolutions (cells along the longest side; 0, the default: the scene's).
  int voxmapResolution() const;
  int shellResolution() const;
  /// Session force model, a vtkBMSessionSource::MethodTypes value (0 the scene's, the default,
  /// 1 Lazar, 2 Zheng).
  int method() const;
  /// Whether the session machines with the panel's tool (true) or the scene's (default).
  bool useChosenTool() const;
  /// Session device, a vtkBMSessionSource::DeviceTypes value (0 scripted, 1 mouse proxy,
  /// 2 Touch). Default 0.
  int deviceType() const;
  /// Force scale, tool N per device N (a Touch session). Default 0, shown as "per tool": the
  /// tool's (bm::SessionForceScale); else in [0.001, 1000].
  double forceScale() const;
  /// Mouse proxy depth below the entry point, mm. Default -2, range [-20, 20].
  double toolDepth() const;
  /// The bone file (.nrrd or .mha) to save the cut bone to and to start from. Default "".
  QString boneFile() const;
  /// Whether a session starts on the bone file's bone instead of the scene's. Default false.
  bool startFromBoneFile() const;
  /// Whether the cut bone is shown with volume rendering. Default false.
  bool volumeRendering() const;
  /// The expected cost line (frame time in ms, force error in %) of the chosen resolutions.
  QString expectedCost() const;
  /// Why a Touch cannot be used ("" when it can; "probing" until the probe answers).
  QString touchStatus() const;
  /// The session status line (setSessionStatus()).
  QString sessionStatus() const;
  /// Whether the busy indicator shows (setBusy()).
  bool isBusy() const;
  /// The Touch probe (tests: wait for its finished() signal).
  qBMTouchProbe* touchProbe() const;

public Q_SLOTS:
  void setVoxmapResolution(int cells);
  void setShellResolution(int cells);
  /// Chooses the device (vtkBMSessionSource::DeviceTypes); unknown values are ignored.
  void setDeviceType(int type);
  /// Chooses the force model (vtkBMSessionSource::MethodTypes); unknown values are ignored.
  void setMethod(int method);
  void setUseChosenTool(bool use);
  /// Sets the force scale (tool N per device N), clamped to its range.
  void setForceScale(double scale);
  /// Sets the mouse proxy depth, mm (clamped to [-20, 20]); emits toolDepthChanged().
  void setToolDepth(double depthMm);
  /// Moves the mouse proxy depth by `steps` single steps (0.1 mm each; positive deeper), as a
  /// wheel over the depth control or the 3D view does.
  void stepToolDepth(int steps);
  void setBoneFile(const QString& path);
  void setStartFromBoneFile(bool start);
  void setVolumeRendering(bool on);
  /// Show the running session's numbers: time (s), depth (mm), removed volume (mm^3), thrust (N),
  /// torque (N mm), frame time p99 (ms) and the force scale in use (tool N per device N; 0: not
  /// shown).
  void setSessionNumbers(double timeS, double depthMm, double removedMm3, double thrustN,
                         double torqueNmm, double frameP99Ms, double forceScale = 0);
  /// Show a one-line session status, and whether a session is running (enables the buttons).
  void setSessionStatus(const QString& message, bool running);
  /// Shows (true) or hides the busy indicator with `message` as the status while a session is
  /// being built; Start is disabled while busy.
  void setBusy(bool busy, const QString& message = QString());
  /// While busy: how far the start has come, 0..1, and its stage (the indicator shows the
  /// percentage; a fraction below 0 shows it busy with no known fraction).
  void setBusyProgress(double fraction, const QString& stage);

public:
  /// Show the session's state (vtkBMSessionSource's StateInfo as bm::SessionState) and why it
  /// paused (bm::ToString(PauseReason), e.g. "overrun"). A paused session checks the Pause
  /// button and labels it Resume, whether the user or the session paused it; otherwise it reads
  /// Pause.
  void setSessionState(bm::SessionState state, const QString& pauseReason);

Q_SIGNALS:
  /// The user asked to start a session with the chosen scene, resolutions and device.
  void startSessionRequested(const QString& scene, int voxmapResolution, int shellResolution,
                             int deviceType);
  /// The user asked to pause (true) or resume (false) the session.
  void pauseSessionRequested(bool paused);
  /// The user asked to stop the session.
  void stopSessionRequested();
  /// The mouse proxy's depth changed, mm.
  void toolDepthChanged(double depthMm);
  /// The user asked to save the session's cut bone to `path` (.nrrd or .mha: a name without an
  /// extension gets .nrrd).
  void saveBoneRequested(const QString& path);
  /// The user switched the volume rendering of the cut bone on or off.
  void volumeRenderingToggled(bool on);

protected:
  bool eventFilter(QObject* watched, QEvent* event) override;
  QScopedPointer<qBMSessionWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMSessionWidget);
  Q_DISABLE_COPY(qBMSessionWidget);
};
