// qBMToolWidget.h - the module panel's tool section: choose a tool type, its display resolution
// and every parameter of the tool model, see what the logic says about it (lips, outer radius,
// axial length, or why its parameters are invalid) and ask to add it to the scene.
//
// Computes nothing: the tool, its parameters and their validation are vtkBMToolSource's; labels
// and tooltips are bm::PanelLogic's (bmPanelLogic.h). Object names (ToolGroupBox, ToolTypeComboBox,
// ToolParametersWidget/<parameter key>, AddToolButton, ...) address it from the GUI tests.
#pragma once

#include <QGroupBox>
#include <QScopedPointer>
#include <QString>

class qBMToolWidgetPrivate;

class qBMToolWidget : public QGroupBox {
  Q_OBJECT
  Q_PROPERTY(int toolType READ toolType WRITE setToolType NOTIFY toolTypeChanged)
  Q_PROPERTY(int resolution READ resolution WRITE setResolution)

public:
  using Superclass = QGroupBox;
  /// The default tool (the twist drill) at 64 facets.
  explicit qBMToolWidget(QWidget* parent = nullptr);
  ~qBMToolWidget() override;

  /// Chosen tool type, a vtkBMToolSource::ToolTypes value (0 drill, 1 reamer, 2 burr). Default 0.
  int toolType() const;
  /// Chosen number of facets around the tool axis for display. Default 64, range [3, 1024].
  int resolution() const;
  /// One line describing the chosen tool (lips, outer radius in mm, axial length in mm), or why
  /// its parameters are invalid.
  QString toolSummary() const;
  /// Whether the edited parameters make a valid tool.
  bool isToolValid() const;
  /// The chosen tool's whole specification as JSON (type and every parameter; units in the key
  /// names), as vtkBMToolSource::GetToolSpecification() gives it; "" when the parameters are
  /// invalid.
  QString toolSpecification() const;
  /// The status line set by setStatusMessage(); empty by default.
  QString statusMessage() const;

public Q_SLOTS:
  /// Choose the tool type (vtkBMToolSource::ToolTypes); out-of-range values are ignored. The
  /// parameter editors are rebuilt at the new type's defaults.
  void setToolType(int type);
  /// Choose the display resolution (facets around the axis); clamped to [3, 1024].
  void setResolution(int facets);
  /// Set one parameter of the chosen tool (a key of its specification, e.g. "radius_mm"; the
  /// unit is in the name). Returns false when the tool has no such parameter. The logic validates
  /// the value; toolSummary() then says what is wrong.
  bool setToolParameter(const QString& key, double value);
  /// Show a one-line status under the tool controls, e.g. what the last action did; "" clears it.
  void setStatusMessage(const QString& message);

Q_SIGNALS:
  /// The tool type changed (vtkBMToolSource::ToolTypes value).
  void toolTypeChanged(int type);
  /// The user asked to add the chosen tool, with its edited and valid parameters
  /// (toolSpecification()), to the scene. Invalid parameters emit nothing and say why in the
  /// status line.
  void addToolRequested(int toolType, int resolution);

protected:
  QScopedPointer<qBMToolWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMToolWidget);
  Q_DISABLE_COPY(qBMToolWidget);
};
