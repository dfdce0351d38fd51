#include "scene_view.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFutureWatcher>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrent>
#include <atomic>

#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/terrain/railway.hpp"

namespace trainsim::studio {
namespace {

// What a build hands back to the GUI thread.
struct Built {
  std::uint64_t request = 0;
  std::uint64_t generation = 0;  // the plan's it was built from
  std::shared_ptr<const sim::EnvironmentStage> stage;
  app::SceneColour colour = app::SceneColour::kMaterial;
  app::ScenePolyData data;
  std::vector<std::shared_ptr<const scene::Tile>> tiles;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d eye = Eigen::Vector3d::Zero(), focus = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
  double seconds = 0.0;
  QString error;
  bool stopped = false;
};

}  // namespace

struct SceneView::Impl {
  std::shared_ptr<const PlanSnapshot> plan;
  std::uint64_t requests = 0;
  QFutureWatcher<Built> watcher;
  std::shared_ptr<std::atomic<bool>> stop;  // the running build's (CancelScope's flag)
  Built built;
  app::SceneColour colour = app::SceneColour::kMaterial;
  long long triangles = 0;

  QVTKOpenGLNativeWidget* widget = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkActor> surfaces, wires;
  QDoubleSpinBox* chainage = nullptr;
  QDoubleSpinBox* radius = nullptr;
  QComboBox* colour_box = nullptr;
  QPushButton* show = nullptr;
  QPushButton* stop_button = nullptr;
  QLabel* status = nullptr;
};

SceneView::SceneView(QWidget* parent) : QWidget(parent), d_(std::make_unique<Impl>()) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  auto* bar = new QHBoxLayout;
  d_->chainage = new QDoubleSpinBox;
  d_->chainage->setObjectName("sceneChainage");
  d_->chainage->setRange(0.0, 1e7);
  d_->chainage->setDecimals(0);
  d_->chainage->setSuffix(" m");
  d_->chainage->setValue(300.0);
  d_->radius = new QDoubleSpinBox;
  d_->radius->setObjectName("sceneRadius");
  d_->radius->setRange(20.0, 2000.0);
  d_->radius->setDecimals(0);
  d_->radius->setSuffix(" m");
  d_->radius->setValue(300.0);
  d_->colour_box = new QComboBox;
  d_->colour_box->setObjectName("sceneColour");
  d_->colour_box->addItems({"materials (as cameras see it)", "classes (as labelled)"});
  d_->show = new QPushButton("Show");
  d_->show->setObjectName("sceneShow");
  d_->show->setToolTip("Build the terrain, track assets and objects within the radius");
  bar->addWidget(new QLabel("main chainage"));
  bar->addWidget(d_->chainage);
  bar->addWidget(new QLabel("radius"));
  bar->addWidget(d_->radius);
  bar->addWidget(new QLabel("colours"));
  bar->addWidget(d_->colour_box);
  d_->stop_button = new QPushButton("Stop");
  d_->stop_button->setObjectName("sceneStop");
  d_->stop_button->setToolTip("Stop building the scene");
  d_->stop_button->setEnabled(false);
  bar->addWidget(d_->show);
  bar->addWidget(d_->stop_button);
  bar->addStretch(1);
  layout->addLayout(bar);
  d_->widget = new QVTKOpenGLNativeWidget;
  d_->widget->setObjectName("scene3d");
  d_->widget->setRenderWindow(d_->window);
  layout->addWidget(d_->widget, 1);
  d_->status = new QLabel("Show builds the scene of the current plan around a chainage.");
  d_->status->setObjectName("sceneStatus");
  layout->addWidget(d_->status);

  d_->window->AddRenderer(d_->renderer);
  d_->renderer->SetBackground(0.62, 0.76, 0.92);
  d_->renderer->AutomaticLightCreationOff();
  vtkNew<vtkLight> sun;  // as trainsim-scene-shot lights it
  sun->SetLightTypeToSceneLight();
  sun->SetPosition(-300.0, -200.0, 600.0);
  sun->SetFocalPoint(0, 0, 0);
  d_->renderer->AddLight(sun);
  for (vtkActor* actor : {d_->surfaces.GetPointer(), d_->wires.GetPointer()}) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetScalarModeToUseCellData();
    mapper->SetColorModeToDirectScalars();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetLineWidth(1.5f);
    actor->GetProperty()->SetAmbient(0.35);
    actor->GetProperty()->SetDiffuse(0.75);
    actor->VisibilityOff();
    d_->renderer->AddActor(actor);
  }

  connect(d_->show, &QPushButton::clicked, this,
          [this] { showScene(d_->chainage->value(), d_->radius->value()); });
  connect(d_->stop_button, &QPushButton::clicked, this, &SceneView::stopBuild);
  connect(d_->colour_box, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [this](int i) { setColour(static_cast<app::SceneColour>(std::max(0, i))); });
  connect(&d_->watcher, &QFutureWatcherBase::finished, this, [this] {
    Built b = d_->watcher.result();
    if (b.request != d_->requests)
      return;  // a newer request is building
    d_->show->setEnabled(true);
    d_->stop_button->setEnabled(false);
    if (b.stopped) {
      d_->status->setText("Building the scene stopped; Show builds it again.");
      return;
    }
    if (!b.error.isEmpty()) {
      d_->status->setText("The scene could not be built: " + b.error);
      return;
    }
    d_->built = std::move(b);
    draw();
    emit sceneShown();
  });
}

// Stops a build still running and waits for it: it holds the plan's stages, not the view, but
// its result would come back to a view that is gone.
SceneView::~SceneView() {
  stopBuild();
  d_->watcher.waitForFinished();
}

void SceneView::stopBuild() {
  if (d_->stop)
    d_->stop->store(true);
}

bool SceneView::building() const {
  return d_->watcher.isRunning();
}

void SceneView::setPlan(std::shared_ptr<const PlanSnapshot> plan) {
  d_->plan = std::move(plan);
  if (d_->plan)
    d_->chainage->setMaximum(d_->plan->plan->route().route.track.length());
  if (!d_->built.tiles.empty())
    showStatus();
}

void SceneView::showStatus() {
  const Built& b = d_->built;
  QString text = QString("%1 tiles, %2 triangles, built in %3 s")
                     .arg(b.tiles.size())
                     .arg(d_->triangles)
                     .arg(b.seconds, 0, 'f', 1);
  if (d_->plan && d_->plan->generation != b.generation)
    text += " — the plan changed since: Show builds the new scene";
  d_->status->setText(text);
}

void SceneView::showScene(double chainage_m, double radius_m) {
  if (!d_->plan) {
    d_->status->setText("No plan yet: the scene is built from the current plan.");
    return;
  }
  d_->chainage->setValue(chainage_m);
  d_->radius->setValue(radius_m);
  const std::uint64_t request = ++d_->requests;
  stopBuild();  // a build still running is superseded
  d_->stop = std::make_shared<std::atomic<bool>>(false);
  d_->show->setEnabled(false);
  d_->stop_button->setEnabled(true);
  d_->status->setText(QString("Building the scene within %1 m of chainage %2 m …")
                          .arg(radius_m, 0, 'f', 0)
                          .arg(chainage_m, 0, 'f', 0));
  // The environment of the plan shown last is kept: a Show elsewhere on the same plan only
  // streams other tiles.
  std::shared_ptr<const sim::EnvironmentStage> stage =
      d_->built.generation == d_->plan->generation ? d_->built.stage : nullptr;
  d_->watcher.setFuture(QtConcurrent::run([plan = d_->plan, stage, colour = d_->colour, request,
                                           chainage_m, radius_m, stop = d_->stop]() mutable {
    const CancelScope scope(stop.get());  // the plan stages and the tiles poll it
    Built b;
    b.request = request;
    b.generation = plan->generation;
    b.radius_m = radius_m;
    b.colour = colour;
    QElapsedTimer timer;
    timer.start();
    try {
      if (!stage)
        stage = sim::makeEnvironment(*plan->plan, *plan->scenario);
      b.stage = stage;
      const terrain::Railway& railway = *stage->railway;
      const double length = railway.main().length();
      const double at_m = std::clamp(chainage_m, 0.0, length);
      const track::TrackFrame at = railway.frame(0, at_m);
      const track::TrackFrame ahead = railway.frame(0, std::min(length, at_m + 0.4 * radius_m));
      b.origin = at.position;
      b.tiles = stage->environment->stream(16)->window(b.origin, radius_m).tiles;
      // From behind and above, to the left, looking along the track as a driver would.
      Eigen::Vector3d left(at.left.x(), at.left.y(), 0.0);
      left.normalize();
      b.eye = -0.15 * radius_m * at.tangent + 0.04 * radius_m * left +
              Eigen::Vector3d(0.0, 0.0, 0.06 * radius_m + 4.0);
      b.focus = ahead.position - b.origin;
      b.data = app::scenePolyData(b.tiles, b.origin, colour);  // here, not on the GUI thread
    } catch (const Cancelled&) {
      b.stopped = true;
    } catch (const std::exception& e) {
      b.error = QString::fromUtf8(e.what());
    }
    b.seconds = timer.elapsed() / 1000.0;
    return b;
  }));
}

void SceneView::setColour(app::SceneColour colour) {
  d_->colour = colour;
  d_->colour_box->blockSignals(true);
  d_->colour_box->setCurrentIndex(static_cast<int>(colour));
  d_->colour_box->blockSignals(false);
  if (!d_->built.tiles.empty())
    draw();
}

void SceneView::draw() {
  Built& b = d_->built;
  if (b.colour != d_->colour || !b.data.surfaces) {
    b.data = app::scenePolyData(b.tiles, b.origin, d_->colour);
    b.colour = d_->colour;
  }
  d_->triangles = b.data.triangles;
  static_cast<vtkPolyDataMapper*>(d_->surfaces->GetMapper())->SetInputData(b.data.surfaces);
  static_cast<vtkPolyDataMapper*>(d_->wires->GetMapper())->SetInputData(b.data.wires);
  d_->surfaces->VisibilityOn();
  d_->wires->VisibilityOn();
  vtkCamera* camera = d_->renderer->GetActiveCamera();
  camera->SetPosition(b.eye.data());
  camera->SetFocalPoint(b.focus.data());
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(50.0);
  camera->SetClippingRange(0.5, 4.0 * b.radius_m);
  showStatus();
  d_->window->Render();
}

long long SceneView::drawnTriangles() const {
  return d_->built.data.surfaces ? d_->built.data.surfaces->GetNumberOfPolys() : 0;
}

std::array<std::uint8_t, 3> SceneView::triangleColour(long long i) const {
  std::array<std::uint8_t, 3> c{};
  vtkUnsignedCharArray::SafeDownCast(d_->built.data.surfaces->GetCellData()->GetScalars())
      ->GetTypedTuple(static_cast<vtkIdType>(i), c.data());
  return c;
}

int SceneView::tileCount() const {
  return static_cast<int>(d_->built.tiles.size());
}
long long SceneView::triangleCount() const {
  return d_->triangles;
}
const std::vector<std::shared_ptr<const scene::Tile>>& SceneView::tiles() const {
  return d_->built.tiles;
}
QString SceneView::status() const {
  return d_->status->text();
}
QImage SceneView::grabImage() {
  d_->window->Render();
  return d_->widget->grabFramebuffer();
}

}  // namespace trainsim::studio
