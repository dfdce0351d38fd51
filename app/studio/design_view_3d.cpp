#include "design_view_3d.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkConeSource.h>
#include <vtkCubeSource.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGlyph3DMapper.h>
#include <vtkLegendBoxActor.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>
#include <vtkUnsignedCharArray.h>
#include <QVBoxLayout>
#include <algorithm>
#include <cstdio>

namespace trainsim::studio {

struct DesignView3D::Impl {
  QVTKOpenGLNativeWidget* widget = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkPolyData> lines;
  vtkNew<vtkActor> track_actor;
  vtkNew<vtkPolyData> violation_points;
  vtkNew<vtkSphereSource> violation_sphere;
  vtkNew<vtkActor> violation_actor;
  vtkNew<vtkCubeSource> train_box;
  vtkNew<vtkActor> train_actor;
  vtkNew<vtkConeSource> pin_cone;
  vtkNew<vtkActor> pin_actor;
  vtkNew<vtkLegendBoxActor> legend;
  std::vector<vtkSmartPointer<vtkBillboardTextActor3D>> labels;
  std::shared_ptr<const PlanSnapshot> plan;
  bool camera_set = false;
  double scene_size = 1000.0;
};

DesignView3D::DesignView3D(QWidget* parent) : QWidget(parent), d_(std::make_unique<Impl>()) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  d_->widget = new QVTKOpenGLNativeWidget(this);
  d_->widget->setObjectName("design3d");
  d_->widget->setRenderWindow(d_->window);
  layout->addWidget(d_->widget);
  d_->window->AddRenderer(d_->renderer);
  d_->renderer->SetBackground(0.96, 0.97, 0.98);
  d_->renderer->SetBackground2(0.80, 0.86, 0.92);
  d_->renderer->GradientBackgroundOn();

  // Tracks: one segment per cell, coloured by the segment's block type.
  vtkNew<vtkPolyDataMapper> track_mapper;
  track_mapper->SetInputData(d_->lines);
  track_mapper->SetScalarModeToUseCellData();
  track_mapper->SetColorModeToDirectScalars();
  d_->track_actor->SetMapper(track_mapper);
  d_->track_actor->GetProperty()->SetLineWidth(3.0);
  d_->track_actor->GetProperty()->SetRenderLinesAsTubes(true);
  d_->renderer->AddActor(d_->track_actor);

  // Violations: red spheres on the main track.
  vtkNew<vtkGlyph3DMapper> glyphs;
  glyphs->SetInputData(d_->violation_points);
  glyphs->SetSourceConnection(d_->violation_sphere->GetOutputPort());
  glyphs->ScalingOff();
  d_->violation_actor->SetMapper(glyphs);
  d_->violation_actor->GetProperty()->SetColor(0.85, 0.1, 0.1);
  d_->violation_actor->GetProperty()->SetOpacity(0.75);
  d_->renderer->AddActor(d_->violation_actor);

  // The train: a box the size of the carbody, and a pin above it to find it from afar.
  vtkNew<vtkPolyDataMapper> box_mapper;
  box_mapper->SetInputConnection(d_->train_box->GetOutputPort());
  d_->train_actor->SetMapper(box_mapper);
  d_->train_actor->GetProperty()->SetColor(0.9, 0.15, 0.15);
  d_->train_actor->VisibilityOff();
  d_->renderer->AddActor(d_->train_actor);
  d_->pin_cone->SetDirection(0, 0, -1);
  d_->pin_cone->SetResolution(24);
  vtkNew<vtkPolyDataMapper> pin_mapper;
  pin_mapper->SetInputConnection(d_->pin_cone->GetOutputPort());
  d_->pin_actor->SetMapper(pin_mapper);
  d_->pin_actor->GetProperty()->SetColor(0.9, 0.15, 0.15);
  d_->pin_actor->VisibilityOff();
  d_->renderer->AddActor(d_->pin_actor);

  // Legend of block colours.
  const auto& types = blockTypes();
  d_->legend->SetNumberOfEntries(static_cast<int>(types.size()) + 1);
  vtkNew<vtkPolyData> symbol;
  {
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(0, 0, 0);
    pts->InsertNextPoint(1, 0, 0);
    pts->InsertNextPoint(1, 1, 0);
    pts->InsertNextPoint(0, 1, 0);
    vtkNew<vtkCellArray> poly;
    const vtkIdType ids[4] = {0, 1, 2, 3};
    poly->InsertNextCell(4, ids);
    symbol->SetPoints(pts);
    symbol->SetPolys(poly);
  }
  for (std::size_t i = 0; i < types.size(); ++i) {
    const Rgb c = blockColour(types[i]);
    double rgb[3] = {c.r / 255.0, c.g / 255.0, c.b / 255.0};
    d_->legend->SetEntry(static_cast<int>(i), symbol, std::string(nameOf(types[i])).c_str(), rgb);
  }
  double red[3] = {0.85, 0.1, 0.1};
  d_->legend->SetEntry(static_cast<int>(types.size()), symbol, "rule violation", red);
  d_->legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  d_->legend->GetPositionCoordinate()->SetValue(0.01, 0.50);
  d_->legend->GetPosition2Coordinate()->SetValue(0.15, 0.48);
  d_->legend->UseBackgroundOn();
  double white[3] = {1, 1, 1};
  d_->legend->SetBackgroundColor(white);
  d_->legend->SetBackgroundOpacity(0.8);
  d_->legend->GetEntryTextProperty()->SetColor(0.1, 0.1, 0.1);
  d_->renderer->AddViewProp(d_->legend);
}

DesignView3D::~DesignView3D() = default;

void DesignView3D::setPlan(std::shared_ptr<const PlanSnapshot> plan) {
  d_->plan = std::move(plan);
  const PlanSnapshot& p = *d_->plan;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();  // world coordinates stay double (1000 km routes)
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const TrackLine& t : p.tracks) {
    const vtkIdType base = points->GetNumberOfPoints();
    for (const Eigen::Vector3d& q : t.points) {
      points->InsertNextPoint(q.data());
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], q[k]);
        hi[k] = std::max(hi[k], q[k]);
      }
    }
    for (std::size_t i = 0; i < t.segment_type.size(); ++i) {
      const vtkIdType ids[2] = {base + static_cast<vtkIdType>(i),
                                base + static_cast<vtkIdType>(i + 1)};
      cells->InsertNextCell(2, ids);
      const Rgb c = blockColour(t.segment_type[i]);
      colours->InsertNextTuple3(c.r, c.g, c.b);
    }
  }
  d_->lines->SetPoints(points);
  d_->lines->SetLines(cells);
  d_->lines->GetCellData()->SetScalars(colours);
  d_->lines->Modified();
  d_->scene_size = std::max({hi[0] - lo[0], hi[1] - lo[1], 100.0});

  vtkNew<vtkPoints> vp;
  vp->SetDataTypeToDouble();
  for (const ViolationMark& v : p.violations)
    vp->InsertNextPoint(v.position.data());
  d_->violation_points->SetPoints(vp);
  d_->violation_points->Modified();
  d_->violation_sphere->SetRadius(std::clamp(d_->scene_size / 250.0, 5.0, 500.0));

  for (auto& l : d_->labels)
    d_->renderer->RemoveActor(l);
  d_->labels.clear();
  for (const ChainageMark& m : p.chainage_marks) {
    vtkNew<vtkBillboardTextActor3D> label;
    char text[32];
    std::snprintf(text, sizeof text, "%.1f km", m.chainage_m / 1000.0);
    label->SetInput(text);
    label->SetPosition(m.position.x(), m.position.y(), m.position.z() + 5.0);
    label->GetTextProperty()->SetFontSize(13);
    label->GetTextProperty()->SetColor(0.15, 0.15, 0.2);
    d_->renderer->AddActor(label);
    d_->labels.emplace_back(label);
  }

  const double pin = std::clamp(d_->scene_size / 60.0, 10.0, 2000.0);
  d_->pin_cone->SetHeight(pin);
  d_->pin_cone->SetRadius(0.3 * pin);
  d_->train_box->SetXLength(p.train_length_m);
  d_->train_box->SetYLength(3.0);
  d_->train_box->SetZLength(4.0);

  if (!d_->camera_set) {
    // Oblique view from the south-west of the whole layout.
    vtkCamera* cam = d_->renderer->GetActiveCamera();
    const double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    cam->SetFocalPoint(c);
    cam->SetPosition(c[0] - 0.3 * d_->scene_size, c[1] - 0.9 * d_->scene_size,
                     c[2] + 0.7 * d_->scene_size);
    cam->SetViewUp(0, 0, 1);
    d_->renderer->ResetCamera();
    cam->Zoom(1.6);  // the bounding sphere of a long, thin layout leaves much empty space
    d_->camera_set = true;
  }
  d_->renderer->ResetCameraClippingRange();
  d_->window->Render();
}

void DesignView3D::markTrain(const TrainPose& pose) {
  vtkNew<vtkTransform> t;
  t->PostMultiply();
  const Eigen::AngleAxisd aa(pose.attitude);
  t->RotateWXYZ(aa.angle() * 180.0 / 3.14159265358979323846, aa.axis().data());
  t->Translate(pose.position.data());
  d_->train_actor->SetUserTransform(t);
  d_->train_actor->VisibilityOn();
  const double h = d_->pin_cone->GetHeight();
  d_->pin_actor->SetPosition(pose.position.x(), pose.position.y(),
                             pose.position.z() + 0.5 * h + 6.0);
  d_->pin_actor->VisibilityOn();
  d_->renderer->ResetCameraClippingRange();
  d_->window->Render();
}

int DesignView3D::segmentCount() const {
  return static_cast<int>(d_->lines->GetNumberOfLines());
}
int DesignView3D::violationCount() const {
  return d_->violation_points->GetPoints()
             ? static_cast<int>(d_->violation_points->GetNumberOfPoints())
             : 0;
}
int DesignView3D::labelCount() const {
  return static_cast<int>(d_->labels.size());
}
bool DesignView3D::trainVisible() const {
  return d_->train_actor->GetVisibility() != 0;
}
Eigen::Vector3d DesignView3D::trainPosition() const {
  double c[3];
  d_->train_actor->GetUserTransform()->TransformPoint(d_->train_box->GetCenter(), c);
  return {c[0], c[1], c[2]};
}

QImage DesignView3D::grabImage() {
  d_->window->Render();
  return d_->widget->grabFramebuffer();
}

}  // namespace trainsim::studio
