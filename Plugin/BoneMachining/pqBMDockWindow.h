// pqBMDockWindow.h - the BoneMachining dock in ParaView: hosts the qBMPanel (Widgets/) and turns
// its requests into ParaView pipeline actions. Glue only; the panel and the logic do the rest.
#pragma once

#include <QDockWidget>

class qBMPanel;

class pqBMDockWindow : public QDockWidget {
  Q_OBJECT
  using Superclass = QDockWidget;

public:
  /// Created by the plugin's dock window interface with the main window as parent.
  explicit pqBMDockWindow(QWidget* parent = nullptr);
  ~pqBMDockWindow() override;

  /// The hosted module panel.
  qBMPanel* panel() const { return this->Panel; }

private Q_SLOTS:
  /// Creates a "BM Tool" source (vtkBMToolSource) with the given ToolType and Resolution on the
  /// active server, applies it and shows it in the active view, if there is one.
  void addTool(int toolType, int resolution);

private:
  Q_DISABLE_COPY(pqBMDockWindow);
  qBMPanel* Panel;
};
