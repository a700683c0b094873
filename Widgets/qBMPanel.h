// qBMPanel.h - the BoneMachining module panel: choose a tool and add it to the scene.
//
// Shows the tool choice (type, display resolution) and what the logic says about the chosen
// tool (lips, outer radius, axial length). It computes nothing: the description comes from the
// logic (vtkBMToolSource), and adding the tool to a scene is left to whoever listens to
// addToolRequested() (the ParaView dock creates a pipeline source).
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

public Q_SLOTS:
  /// Choose the tool type (vtkBMToolSource::ToolTypes); out-of-range values are ignored.
  void setToolType(int type);
  /// Choose the display resolution (facets around the axis); clamped to [3, 1024].
  void setResolution(int facets);
  /// Show a one-line status under the tool controls, e.g. what the last action did; "" clears it.
  void setStatusMessage(const QString& message);

Q_SIGNALS:
  /// The tool type changed (vtkBMToolSource::ToolTypes value).
  void toolTypeChanged(int type);
  /// The user asked to add the chosen tool to the scene.
  void addToolRequested(int toolType, int resolution);

protected:
  QScopedPointer<qBMPanelPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPanel);
  Q_DISABLE_COPY(qBMPanel);
};
