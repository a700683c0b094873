// qBMChartsWidget.cxx - see qBMChartsWidget.h.
#include "qBMChartsWidget.h"

#include "QVTKOpenGLNativeWidget.h"
#include "vtkAxis.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkDoubleArray.h"
#include "vtkGenericOpenGLRenderWindow.h"
#include "vtkNew.h"
#include "vtkPlot.h"
#include "vtkTable.h"

#include <QVBoxLayout>

namespace {
/// Columns of the history table the charts read (vtkBMSessionSource's output port 2).
const char* const kHistoryColumns[] = {"time_s", "thrust_N", "torque_Nmm", "frame_ms"};
/// Rows kept: 10 minutes at the session's 10 ms history step.
constexpr vtkIdType kMaxRows = 60000;
} // namespace

class qBMChartsWidgetPrivate {
  Q_DECLARE_PUBLIC(qBMChartsWidget);

public:
  explicit qBMChartsWidgetPrivate(qBMChartsWidget& object) : q_ptr(&object) {}
  void init();
  /// A chart of `leftColumn` (and `rightColumn` on the right axis) against time.
  QVTKOpenGLNativeWidget* addChart(vtkChartXY* chart, vtkContextView* view, const char* title,
                                   const char* leftColumn, const char* rightColumn);
  /// The overrun rows (frame_ms over the period) as their own table, the title, and a redraw.
  void update();
  vtkDoubleArray* column(vtkTable* table, int i) const {
    return vtkDoubleArray::SafeDownCast(table->GetColumnByName(kHistoryColumns[i]));
  }

  qBMChartsWidget* const q_ptr;
  vtkNew<vtkTable> History;
  /// The rows of History whose frame time is over the period.
  vtkNew<vtkTable> Overruns;
  double PeriodMs = 1.0;
  vtkNew<vtkContextView> ForceView, FrameView;
  vtkNew<vtkChartXY> ForceChart, FrameChart;
  vtkPlot* OverrunPlot = nullptr;
  QVTKOpenGLNativeWidget* ForceChartWidget = nullptr;
  QVTKOpenGLNativeWidget* FrameChartWidget = nullptr;
};

QVTKOpenGLNativeWidget* qBMChartsWidgetPrivate::addChart(vtkChartXY* chart, vtkContextView* view,
                                                         const char* title, const char* leftColumn,
                                                         const char* rightColumn) {
  Q_Q(qBMChartsWidget);
  auto* widget = new QVTKOpenGLNativeWidget(q);
  widget->setMinimumHeight(140);
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  widget->setRenderWindow(window);
  view->SetRenderWindow(window);
  view->GetScene()->AddItem(chart);
  chart->SetTitle(title);
  chart->SetShowLegend(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
  vtkPlot* left = chart->AddPlot(vtkChart::LINE);
  left->SetInputData(this->History, "time_s", leftColumn);
  left->SetColor(30, 90, 200, 255);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(leftColumn);
  if (rightColumn) {
    vtkPlot* right = chart->AddPlot(vtkChart::LINE);
    right->SetInputData(this->History, "time_s", rightColumn);
    right->SetColor(200, 60, 40, 255);
    chart->SetPlotCorner(right, 1); // right axis: N mm beside N
    chart->GetAxis(vtkAxis::RIGHT)->SetTitle(rightColumn);
  }
  q->layout()->addWidget(widget);
  return widget;
}

void qBMChartsWidgetPrivate::init() {
  Q_Q(qBMChartsWidget);
  auto* layout = new QVBoxLayout(q);
  layout->setContentsMargins(0, 0, 0, 0);
  for (vtkTable* table : {this->History.GetPointer(), this->Overruns.GetPointer()})
    for (const char* name : kHistoryColumns) {
      vtkNew<vtkDoubleArray> column;
      column->SetName(name);
      table->AddColumn(column);
    }
  this->ForceChartWidget = this->addChart(this->ForceChart, this->ForceView,
                                          "Thrust (N) and torque (N mm)", "thrust_N", "torque_Nmm");
  this->ForceChartWidget->setObjectName("ForceChartWidget");
  this->FrameChartWidget =
      this->addChart(this->FrameChart, this->FrameView, "", "frame_ms", nullptr);
  this->FrameChartWidget->setObjectName("FrameChartWidget");
  this->OverrunPlot = this->FrameChart->AddPlot(vtkChart::POINTS);
  this->OverrunPlot->SetInputData(this->Overruns, "time_s", "frame_ms");
  this->OverrunPlot->SetColor(220, 30, 30, 255);
  this->OverrunPlot->SetLabel("overrun");
  q->setToolTip(qBMChartsWidget::tr("Thrust (N), torque (N mm) and haptic frame time (ms) of "
                                    "the session; frames over the period are marked in red"));
  this->update();
}

void qBMChartsWidgetPrivate::update() {
  vtkDoubleArray* frame = this->column(this->History, 3);
  for (int c = 0; c < 4; ++c)
    this->column(this->Overruns, c)->SetNumberOfTuples(0);
  for (vtkIdType r = 0; r < frame->GetNumberOfTuples(); ++r)
    if (frame->GetValue(r) > this->PeriodMs)
      for (int c = 0; c < 4; ++c)
        this->column(this->Overruns, c)
            ->InsertNextValue(this->column(this->History, c)->GetValue(r));
  this->Overruns->Modified();
  this->FrameChart->SetTitle(this->q_ptr->frameChartTitle().toUtf8().constData());
  // A line needs two points: the plots stay hidden until the history has them.
  const bool drawable = this->History->GetNumberOfRows() >= 2;
  for (vtkChartXY* chart : {this->ForceChart.GetPointer(), this->FrameChart.GetPointer()}) {
    for (vtkIdType i = 0; i < chart->GetNumberOfPlots(); ++i)
      chart->GetPlot(i)->SetVisible(drawable);
    if (drawable)
      chart->RecalculateBounds();
  }
  this->OverrunPlot->SetVisible(drawable && this->Overruns->GetNumberOfRows() > 0);
  for (QVTKOpenGLNativeWidget* widget : {this->ForceChartWidget, this->FrameChartWidget})
    if (widget->isVisible())
      widget->renderWindow()->Render();
}

qBMChartsWidget::qBMChartsWidget(QWidget* parent)
    : Superclass(parent), d_ptr(new qBMChartsWidgetPrivate(*this)) {
  Q_D(qBMChartsWidget);
  d->init();
}

qBMChartsWidget::~qBMChartsWidget() = default;

int qBMChartsWidget::historyRows() const {
  Q_D(const qBMChartsWidget);
  return int(d->History->GetNumberOfRows());
}

int qBMChartsWidget::overrunRows() const {
  Q_D(const qBMChartsWidget);
  return int(d->Overruns->GetNumberOfRows());
}

double qBMChartsWidget::framePeriodMs() const {
  Q_D(const qBMChartsWidget);
  return d->PeriodMs;
}

QString qBMChartsWidget::frameChartTitle() const {
  return tr("Haptic frame time (ms): %1 over the %2 ms period")
      .arg(this->overrunRows())
      .arg(this->framePeriodMs(), 0, 'g', 3);
}

void qBMChartsWidget::setFramePeriodMs(double periodMs) {
  Q_D(qBMChartsWidget);
  if (!(periodMs > 0))
    return;
  d->PeriodMs = periodMs;
  d->update();
}

void qBMChartsWidget::clearHistory() {
  this->setHistory(nullptr);
}

void qBMChartsWidget::setHistory(vtkTable* history) {
  Q_D(qBMChartsWidget);
  vtkDataArray* theirs[4] = {};
  vtkIdType rows = history ? history->GetNumberOfRows() : 0;
  for (int c = 0; c < 4 && history; ++c) {
    theirs[c] = vtkDataArray::SafeDownCast(history->GetColumnByName(kHistoryColumns[c]));
    if (!theirs[c])
      rows = 0; // not a session history: nothing to draw
  }
  vtkDoubleArray* time = d->column(d->History, 0);
  const vtkIdType held = time->GetNumberOfTuples();
  if (!history ||
      (rows > 0 && held > 0 && theirs[0]->GetComponent(rows - 1, 0) < time->GetValue(held - 1)))
    for (int c = 0; c < 4; ++c) // cleared, or a new session (its time went back)
      d->column(d->History, c)->SetNumberOfTuples(0);
  const double last =
      time->GetNumberOfTuples() > 0 ? time->GetValue(time->GetNumberOfTuples() - 1) : -1e300;
  for (vtkIdType r = 0; r < rows; ++r)
    if (theirs[0]->GetComponent(r, 0) > last)
      for (int c = 0; c < 4; ++c)
        d->column(d->History, c)->InsertNextValue(theirs[c]->GetComponent(r, 0));
  const vtkIdType extra = time->GetNumberOfTuples() - kMaxRows;
  if (extra > 0)
    for (int c = 0; c < 4; ++c) { // the oldest rows go
      vtkDoubleArray* column = d->column(d->History, c);
      for (vtkIdType r = 0; r < kMaxRows; ++r)
        column->SetValue(r, column->GetValue(r + extra));
      column->SetNumberOfTuples(kMaxRows);
    }
  d->History->Modified();
  d->update();
}
