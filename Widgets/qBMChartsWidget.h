// qBMChartsWidget.h - the module panel's live charts of a session: thrust (N) and torque (N mm),
// and the haptic frame time (ms) with the frames over the period marked, against session time (s).
//
// Keeps its own history: each setHistory() appends the rows newer than those it holds, so the
// charts keep what they showed across pauses and beyond the session's own window; a table whose
// time went back (a new session) starts them again. Draws with VTK's chart views
// (QVTKOpenGLNativeWidget + vtkChartXY; object names ForceChartWidget and FrameChartWidget).
#pragma once

#include <QScopedPointer>
#include <QWidget>

class qBMChartsWidgetPrivate;
class vtkTable;

class qBMChartsWidget : public QWidget {
  Q_OBJECT

public:
  using Superclass = QWidget;
  explicit qBMChartsWidget(QWidget* parent = nullptr);
  ~qBMChartsWidget() override;

  /// Rows of history the charts hold.
  int historyRows() const;
  /// Rows whose frame time is over the period (overruns), as the frame chart marks them.
  int overrunRows() const;
  /// The haptic frame period, ms (default 1: 1 kHz); frames longer than it are overruns.
  double framePeriodMs() const;
  /// The frame chart's title: the frame time and how many rows overran.
  QString frameChartTitle() const;

public Q_SLOTS:
  /// Appends the session's history rows newer than the last one held: a table with the columns
  /// time_s, thrust_N, torque_Nmm and frame_ms (vtkBMSessionSource's output port 2). A table
  /// ending before the last row held (a new session) replaces the history; null clears it.
  void setHistory(vtkTable* history);
  /// Empties the charts.
  void clearHistory();
  /// Sets the frame period, ms (> 0; others are ignored).
  void setFramePeriodMs(double periodMs);

protected:
  QScopedPointer<qBMChartsWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMChartsWidget);
  Q_DISABLE_COPY(qBMChartsWidget);
};
