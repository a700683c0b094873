// qBMPanel.h - the BoneMachining module panel: its sections, one widget per concept, over the
// Qt-free module logic (bmPanelLogic.h and the vtkBM* sources):
//   qBMToolWidget     choose a tool and its parameters, add it to the scene;
//   qBMCTWidget       a CT's bone (threshold, region, preview) and the entry and axis on it;
//   qBMPlanWidget     glenoid planning: landmarks, measured and target angles, the axis, steps;
//   qBMSessionWidget  run a machining session (scene, resolutions and their expected cost, force
//                     model, device, force scale, depth, bone file, start / pause / stop);
//   qBMChartsWidget   the session's live thrust, torque and frame-time charts.
// The panel lays them out and hands them to whoever drives them (the ParaView dock,
// Plugin/BoneMachining/pqBMDockWindow.h). Docs/Plugin.md describes the panel.
#pragma once

#include <QScopedPointer>
#include <QWidget>

class qBMCTWidget;
class qBMChartsWidget;
class qBMPanelPrivate;
class qBMPlanWidget;
class qBMSessionWidget;
class qBMToolWidget;

class qBMPanel : public QWidget {
  Q_OBJECT

public:
  using Superclass = QWidget;
  /// A panel with its five sections at their defaults (object name "qBMPanel").
  explicit qBMPanel(QWidget* parent = nullptr);
  ~qBMPanel() override;

  /// The tool section (object name ToolGroupBox).
  qBMToolWidget* toolWidget() const;
  /// The CT section (object name CTGroupBox).
  qBMCTWidget* ctWidget() const;
  /// The Planning section (object name PlanGroupBox).
  qBMPlanWidget* planWidget() const;
  /// The session section (object name SessionGroupBox).
  qBMSessionWidget* sessionWidget() const;
  /// The charts under the session section (object name ChartsWidget).
  qBMChartsWidget* chartsWidget() const;

protected:
  QScopedPointer<qBMPanelPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPanel);
  Q_DISABLE_COPY(qBMPanel);
};
