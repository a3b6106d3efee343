#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include "laserfit/core/error.hpp"
#include "laserfit/report/figures.hpp"
#include "png.hpp"

namespace laserfit::report {

void render_overlay(const std::string& path, const PointCloud& cloud,
                    const Eigen::Vector3d& viewpoint, const std::string& title, int width,
                    int height) {
  if (!have_display()) throw Error(path, "no X display for VTK (run under xvfb-run)");
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  colours->SetName("colour");
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  size_t n = 0;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const auto& p = cloud.points[i];
    if (!p.allFinite()) continue;
    const bool ref = !cloud.labels.empty() && cloud.labels[i] == 1;
    const vtkIdType id = pts->InsertNextPoint(p.x(), p.y(), p.z());
    verts->InsertNextCell(1, &id);
    const unsigned char scan_c[3] = {90, 90, 90}, ref_c[3] = {230, 120, 0};
    colours->InsertNextTypedTuple(ref ? ref_c : scan_c);
    if (ref) centre += p.cast<double>(), ++n;
  }
  if (n == 0) throw Error(path, "overlay has no reference points");
  centre /= double(n);
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetVerts(verts);
  poly->GetPointData()->SetScalars(colours);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetPointSize(2);
  vtkNew<vtkRenderer> ren;
  ren->SetBackground(1, 1, 1);
  ren->AddActor(actor);
  vtkNew<vtkTextActor> text;
  text->SetInput(title.c_str());
  text->GetTextProperty()->SetFontSize(18);
  text->GetTextProperty()->SetColor(0, 0, 0);
  text->SetDisplayPosition(10, height - 30);
  ren->AddActor2D(text);
  vtkNew<vtkTextActor> legend;
  legend->SetInput("grey: scan    orange: registered reference");
  legend->GetTextProperty()->SetFontSize(14);
  legend->GetTextProperty()->SetColor(0.2, 0.2, 0.2);
  legend->SetDisplayPosition(10, 10);
  ren->AddActor2D(legend);
  // From the sensor towards the part, as the scanner saw it.
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetFocalPoint(centre.data());
  cam->SetPosition(viewpoint.data());
  Eigen::Vector3d dir = (centre - viewpoint).normalized();
  Eigen::Vector3d up =
      std::abs(dir.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
  cam->SetViewUp(up.data());
  ren->ResetCamera();
  cam->Zoom(1.3);
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetSize(width, height);
  win->AddRenderer(ren);
  win->Render();
  write_png(path, win);
}

}  // namespace laserfit::report
