#include "bmSpeedAccuracyChart.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContext2D.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlotLine.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "bmVirtualDisplay.h"

namespace {

// Points that also draw a text label beside each point. vtkPlotPoints paints in the chart's
// data space, which is log10 of the data on log axes; labels are placed the same way.
class LabeledPoints : public vtkPlotPoints {
public:
  static LabeledPoints* New();
  vtkTypeMacro(LabeledPoints, vtkPlotPoints);
  std::vector<std::array<double, 2>> At;
  std::vector<std::string> Labels;
  bool LogX = false, LogY = false;

  bool Paint(vtkContext2D* painter) override {
    if (!this->Superclass::Paint(painter))
      return false;
    if (!this->Visible)
      return true;
    painter->GetTextProp()->SetFontSize(11);
    painter->GetTextProp()->SetColor(0.15, 0.15, 0.15);
    painter->GetTextProp()->SetJustificationToLeft();
    painter->GetTextProp()->SetVerticalJustificationToBottom();
    for (size_t i = 0; i < At.size(); ++i) {
      const float x = float(LogX ? std::log10(At[i][0]) : At[i][0]);
      const float y = float(LogY ? std::log10(At[i][1]) : At[i][1]);
      painter->DrawString(x, y, (" " + Labels[i]).c_str());
    }
    return true;
  }
};
vtkStandardNewMacro(LabeledPoints);

} // namespace

namespace bm {

void WriteSpeedAccuracyChart(const std::string& pngPath, const std::string& title,
                             const std::vector<ChartSeries>& series, double budgetMs, int width,
                             int height, const std::string& yTitle) {
  double xLo = budgetMs, xHi = budgetMs, yLo = 1e300, yHi = 0;
  for (const auto& s : series)
    for (const auto& p : s.points) {
      if (!(p.x > 0))
        continue;
      xLo = std::min(xLo, p.x);
      xHi = std::max(xHi, p.x);
      yHi = std::max(yHi, p.y);
      if (p.y > 0)
        yLo = std::min(yLo, p.y);
    }
  if (!(yHi > 0))
    throw std::runtime_error("speed/accuracy chart: no point to draw");
  const double floorY = std::max(yLo, 1e-6); // errors below it (or 0) are drawn at the floor
  VirtualDisplay::Ensure();

  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(width, height);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetTitle(title);
  chart->GetTitleProperties()->SetFontSize(18);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  vtkAxis* ax = chart->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* ay = chart->GetAxis(vtkAxis::LEFT);
  ax->SetTitle("frame time, ms (log)");
  ay->SetTitle(yTitle);
  ax->SetLogScale(true);
  ay->SetLogScale(true);
  ax->SetBehavior(vtkAxis::FIXED);
  ay->SetBehavior(vtkAxis::FIXED);
  ax->SetUnscaledRange(xLo / 2, xHi * 3);
  ay->SetUnscaledRange(floorY / 2, yHi * 3);

  static const unsigned char colors[][3] = {{31, 119, 180}, {214, 39, 40},   {44, 160, 44},
                                            {255, 127, 14}, {148, 103, 189}, {140, 86, 75}};
  static const int markers[] = {vtkPlotPoints::CIRCLE, vtkPlotPoints::SQUARE,
                                vtkPlotPoints::DIAMOND, vtkPlotPoints::CROSS, vtkPlotPoints::PLUS};
  std::vector<vtkSmartPointer<vtkTable>> tables;
  for (size_t si = 0; si < series.size(); ++si) {
    const auto& s = series[si];
    vtkNew<vtkTable> t;
    vtkNew<vtkDoubleArray> xs, ys;
    xs->SetName("frame time, ms");
    ys->SetName(s.name.c_str());
    t->AddColumn(xs);
    t->AddColumn(ys);
    auto plot = vtkSmartPointer<LabeledPoints>::New();
    for (const auto& p : s.points) {
      if (!(p.x > 0))
        continue;
      xs->InsertNextValue(p.x);
      ys->InsertNextValue(std::max(p.y, floorY));
      plot->At.push_back({p.x, std::max(p.y, floorY)});
      plot->Labels.push_back(p.label);
    }
    if (xs->GetNumberOfTuples() == 0)
      continue;
    tables.push_back(t);
    plot->LogX = plot->LogY = true;
    plot->SetInputData(t, 0, 1);
    const auto* c = colors[si % 6];
    plot->SetColor(c[0], c[1], c[2], 255);
    plot->SetMarkerStyle(markers[si % 5]);
    plot->SetMarkerSize(10);
    plot->SetLabel(s.name);
    chart->AddPlot(plot);
  }
  // The haptic budget: a vertical line at budgetMs across the error range.
  vtkNew<vtkTable> budget;
  vtkNew<vtkDoubleArray> bx, by;
  bx->SetName("budget x");
  by->SetName("1 ms haptic budget");
  budget->AddColumn(bx);
  budget->AddColumn(by);
  bx->InsertNextValue(budgetMs);
  by->InsertNextValue(floorY / 2);
  bx->InsertNextValue(budgetMs);
  by->InsertNextValue(yHi * 3);
  vtkPlot* line = chart->AddPlot(vtkChart::LINE);
  line->SetInputData(budget, 0, 1);
  line->SetColor(0, 0, 0, 255);
  line->SetWidth(2.0);
  line->GetPen()->SetLineType(vtkPen::DASH_LINE);
  line->SetLabel(std::to_string(budgetMs).substr(0, 4) + " ms haptic budget");

  view->GetRenderWindow()->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(view->GetRenderWindow());
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(pngPath.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0)
    throw std::runtime_error("speed/accuracy chart: cannot write " + pngPath);
}

} // namespace bm
