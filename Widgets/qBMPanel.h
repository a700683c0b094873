// qBMPanel.h - the BoneMachining module panel: choose a tool and add it to the scene; run a
// machining session (scene, resolutions, device, start / pause / stop) and read its numbers.
//
// Shows the tool choice (type, display resolution) and what the logic says about the chosen
// tool (lips, outer radius, axial length). It computes nothing: the description comes from the
// logic (vtkBMToolSource); adding the tool to a scene and running sessions are left to whoever
// listens to the requests (the ParaView dock creates pipeline sources, vtkBMSessionSource for a
// session, and feeds the session's numbers back through setSessionNumbers()).
#pragma once

#include <QScopedPointer>
#include <QString>
#include <QWidget>

class qBMPanelPrivate;

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
  /// Session device, a vtkBMSessionSource::DeviceTypes value (0 scripted, 1 mouse proxy).
  int deviceType() const;
  /// Mouse proxy depth below the entry point, mm. Default -2.
  double toolDepth() const;

public Q_SLOTS:
  /// Choose the tool type (vtkBMToolSource::ToolTypes); out-of-range values are ignored.
  void setToolType(int type);
  /// Choose the display resolution (facets around the axis); clamped to [3, 1024].
  void setResolution(int facets);
  /// Show a one-line status under the tool controls, e.g. what the last action did; "" clears it.
  void setStatusMessage(const QString& message);
  /// Choose the session's resolutions (0 = the scene's) and device.
  void setVoxmapResolution(int cells);
  void setShellResolution(int cells);
  void setDeviceType(int type);
  /// Show the running session's numbers: time (s), depth (mm), removed volume (mm^3), thrust (N),
  /// torque (N mm), frame time p99 (ms).
  void setSessionNumbers(double timeS, double depthMm, double removedMm3, double thrustN,
                         double torqueNmm, double frameP99Ms);
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

protected:
  QScopedPointer<qBMPanelPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPanel);
  Q_DISABLE_COPY(qBMPanel);
};
