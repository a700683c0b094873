// bmReportCharts.cxx - see bmReportCharts.h.
#include "bmReportCharts.h"

#include <algorithm>
#include <stdexcept>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "bmSurfaceImage.h"
#include "bmVirtualDisplay.h"

namespace bm {

void WriteLineChartPng(const std::string& path, const LineChart& chart) {
  if (chart.x.empty() || chart.series.empty())
    throw std::runtime_error("chart '" + chart.title + "': nothing to draw");
  VirtualDisplay::Ensure();

  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> xs;
  xs->SetName(chart.xLabel.c_str());
  const vtkIdType n = vtkIdType(chart.x.size());
  xs->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i)
    xs->SetValue(i, chart.x[size_t(i)]);
  table->AddColumn(xs);
  for (const auto& s : chart.series) {
    vtkNew<vtkDoubleArray> ys;
    ys->SetName(s.name.c_str());
    ys->SetNumberOfValues(n);
    for (vtkIdType i = 0; i < n; ++i)
      ys->SetValue(i, size_t(i) < s.y.size() ? s.y[size_t(i)] : s.y.back());
    table->AddColumn(ys);
  }

  vtkNew<vtkContextView> view;
  vtkRenderWindow* window = view->GetRenderWindow();
  window->SetOffScreenRendering(1);
  window->SetSize(chart.widthPx, chart.heightPx);
  window->SetMultiSamples(0);
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  vtkNew<vtkChartXY> xy;
  view->GetScene()->AddItem(xy);
  xy->SetTitle(chart.title);
  xy->GetTitleProperties()->SetFontSize(16);
  xy->GetAxis(vtkAxis::BOTTOM)->SetTitle(chart.xLabel);
  xy->GetAxis(vtkAxis::LEFT)->SetTitle(chart.yLabel);
  for (size_t s = 0; s < chart.series.size(); ++s) {
    vtkPlot* line = xy->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, vtkIdType(s + 1));
    const auto& c = chart.series[s].rgb;
    line->SetColor(c[0], c[1], c[2], 255);
    line->SetWidth(1.5);
  }
  xy->SetShowLegend(chart.series.size() > 1);
  if (chart.series.size() > 1)
    xy->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  WritePng(path, grab->GetOutput());
}

} // namespace bm
