#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPlot.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <cstdlib>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/report/figures.hpp"
#include "png.hpp"

namespace laserfit::report {

bool have_display() {
  const char* d = std::getenv("DISPLAY");
  return d && *d;
}

void write_png(const std::string& path, vtkRenderWindow* window) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> png;
  png->SetWriteToMemory(1);
  png->SetInputConnection(grab->GetOutputPort());
  png->Write();
  vtkUnsignedCharArray* bytes = png->GetResult();
  if (!bytes || bytes->GetNumberOfTuples() == 0) throw Error(path, "VTK produced no image");
  write_file_atomic(path, std::string(reinterpret_cast<const char*>(bytes->GetPointer(0)),
                                      size_t(bytes->GetNumberOfTuples())));
}

void render_chart(const std::string& path, const std::vector<Series>& series,
                  const ChartSettings& s) {
  if (!have_display()) throw Error(path, "no X display for VTK (run under xvfb-run)");
  // Colour-blind-safe palette (Okabe & Ito 2008).
  static const unsigned char palette[][3] = {{0, 114, 178},   {230, 159, 0},  {0, 158, 115},
                                             {204, 121, 167}, {86, 180, 233}, {213, 94, 0},
                                             {240, 228, 66},  {0, 0, 0}};
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(s.width, s.height);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetTitle(s.title);
  chart->GetTitleProperties()->SetFontSize(18);
  chart->SetShowLegend(series.size() > 1);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::BOTTOM);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(s.x_label);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(s.y_label);
  if (s.log_x) chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(true);
  if (s.y_max > s.y_min) {
    chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::LEFT)->SetRange(s.y_min, s.y_max);
  }
  std::vector<vtkSmartPointer<vtkTable>> tables;  // the plots keep pointers to their tables
  for (size_t k = 0; k < series.size(); ++k) {
    const auto& se = series[k];
    if (se.x.empty()) continue;
    auto table = vtkSmartPointer<vtkTable>::New();
    vtkNew<vtkDoubleArray> x, y;
    x->SetName("x");
    y->SetName(se.name.c_str());
    table->AddColumn(x);
    table->AddColumn(y);
    table->SetNumberOfRows(vtkIdType(se.x.size()));
    for (size_t i = 0; i < se.x.size(); ++i) {
      table->SetValue(vtkIdType(i), 0, se.x[i]);
      table->SetValue(vtkIdType(i), 1, se.y[i]);
    }
    tables.push_back(table);
    vtkPlot* plot = chart->AddPlot(s.points ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    const auto* c = palette[k % 8];
    plot->SetColor(c[0], c[1], c[2], 255);
    plot->SetWidth(s.points ? 1.0f : 2.5f);
  }
  view->GetRenderWindow()->Render();
  write_png(path, view->GetRenderWindow());
}

}  // namespace laserfit::report
