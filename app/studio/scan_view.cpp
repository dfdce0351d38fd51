#include "scan_view.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <Eigen/Core>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QEvent>
#include <QFile>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMouseEvent>
#include <QPixmap>
#include <QSlider>
#include <QSpinBox>
#include <QSplitter>
#include <QTableWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <vector>

#include "dataset_files.hpp"
#include "trainsim/camera/kitti_projection.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/io/kitti_calib.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/scene/semantics.hpp"

namespace trainsim::studio {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

}  // namespace

// The class table's colours, but unlabelled (black in the table, as SemanticKITTI has it) in
// mid grey, which shows on the view's dark background; ids the table does not have in white.
std::array<std::uint8_t, 3> ScanView::classColour(std::uint32_t id) {
  const auto table = scene::classes();
  if (id == 0)
    return {128, 128, 128};
  return id < table.size() ? table[id].colour : Rgb{255, 255, 255};
}

namespace {

// An instance id's colour: hues a golden angle apart, so neighbouring ids differ; 0 (no
// instance: stuff) in grey.
Rgb instanceColour(std::uint64_t id) {
  if (id == 0)
    return {150, 150, 150};
  const double hue = std::fmod(static_cast<double>(id) * 0.618033988749895, 1.0) * 6.0;
  const double f = hue - std::floor(hue);
  const auto c = [](double v) { return static_cast<std::uint8_t>(std::lround(55.0 + 200.0 * v)); };
  switch (static_cast<int>(hue)) {
    case 0:
      return {c(1), c(f), c(0)};
    case 1:
      return {c(1 - f), c(1), c(0)};
    case 2:
      return {c(0), c(1), c(f)};
    case 3:
      return {c(0), c(1 - f), c(1)};
    case 4:
      return {c(f), c(0), c(1)};
    default:
      return {c(1), c(0), c(1 - f)};
  }
}

}  // namespace

// A value in [0, 1] on a dark-blue → teal → yellow ramp (perceptually ordered, as viridis).
std::array<std::uint8_t, 3> ScanView::ramp(double t) {
  t = std::clamp(t, 0.0, 1.0);
  static constexpr double kStops[3][3] = {{68, 1, 84}, {33, 145, 140}, {253, 231, 37}};
  const int i = t < 0.5 ? 0 : 1;
  const double u = t < 0.5 ? 2.0 * t : 2.0 * t - 1.0;
  Rgb out{};
  for (int k = 0; k < 3; ++k)
    out[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(
        std::lround(kStops[i][k] + u * (kStops[i + 1][k] - kStops[i][k])));
  return out;
}

namespace {

// The frame's images of one camera that a pixel's description reads, loaded on first use.
struct PixelImages {
  int frame = -1, camera = -1;
  std::optional<io::PngImage> semantic, instance, depth;
};

}  // namespace

struct ScanView::Impl {
  QString sequence;                      // absolute path of sequences/NN
  std::map<int, InstanceRow> instances;  // instances.csv
  mutable PixelImages pixel_images;      // the frame's images describePixel() reads
  QString pixel;                         // the last click's description, in the status line
  QStringList lidars, cameras;
  int frames = 0, frame = 0, lidar = 0, camera = 0;
  Colour colour = Colour::kClass;
  Picture picture_kind = Picture::kRgb;
  std::vector<float> xyzi;            // the scan: x y z intensity per point
  std::vector<std::uint32_t> labels;  // class | instance << 16 per point
  QImage base, picture;               // the camera's picture, and with the points drawn on it
  bool overlay = false;
  io::KittiCalib calib;
  std::optional<camera::KittiProjection> projection;  // of the shown LiDAR into the shown camera
  QString scan_problem, picture_problem, overlay_problem;  // shown in the status line
  bool unit_intensity = true;  // intensities in 0..1 (else the VLP-16's 0..255)
  bool camera_placed = false;

  QVTKOpenGLNativeWidget* widget = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkPolyData> cloud;
  vtkNew<vtkUnsignedCharArray> colours;
  vtkNew<vtkActor> actor;

  QComboBox* lidar_box = nullptr;
  QComboBox* camera_box = nullptr;
  QComboBox* colour_box = nullptr;
  QComboBox* picture_box = nullptr;
  QCheckBox* overlay_box = nullptr;
  QSpinBox* frame_spin = nullptr;
  QSlider* frame_slider = nullptr;
  QLabel* image = nullptr;
  QTableWidget* counts = nullptr;
  QLabel* status = nullptr;
};

ScanView::ScanView(QWidget* parent) : QWidget(parent), d_(std::make_unique<Impl>()) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  auto* bar = new QHBoxLayout;
  d_->lidar_box = new QComboBox;
  d_->lidar_box->setObjectName("scanLidar");
  d_->camera_box = new QComboBox;
  d_->camera_box->setObjectName("scanCamera");
  d_->colour_box = new QComboBox;
  d_->colour_box->setObjectName("scanColour");
  d_->colour_box->addItems({"class", "instance", "intensity", "height"});
  d_->picture_box = new QComboBox;
  d_->picture_box->setObjectName("scanPicture");
  d_->picture_box->addItems({"RGB", "semantic", "depth", "instances"});
  d_->overlay_box = new QCheckBox("LiDAR on picture");
  d_->overlay_box->setObjectName("scanOverlay");
  d_->overlay_box->setToolTip(
      "Draw the scan's points on the picture where calib.txt projects them, in the scan's "
      "colours");
  d_->frame_spin = new QSpinBox;
  d_->frame_spin->setObjectName("scanFrame");
  d_->frame_spin->setKeyboardTracking(false);  // a typed number loads once, when it is whole
  d_->frame_slider = new QSlider(Qt::Horizontal);
  d_->frame_slider->setTracking(false);  // a drag loads the frame it ends on
  bar->addWidget(new QLabel("LiDAR"));
  bar->addWidget(d_->lidar_box);
  bar->addWidget(new QLabel("colour by"));
  bar->addWidget(d_->colour_box);
  bar->addWidget(new QLabel("camera"));
  bar->addWidget(d_->camera_box);
  bar->addWidget(d_->picture_box);
  bar->addWidget(d_->overlay_box);
  bar->addWidget(new QLabel("frame"));
  bar->addWidget(d_->frame_spin);
  bar->addWidget(d_->frame_slider, 1);
  layout->addLayout(bar);

  auto* split = new QSplitter(Qt::Horizontal);
  d_->widget = new QVTKOpenGLNativeWidget;
  d_->widget->setObjectName("scan3d");
  d_->widget->setRenderWindow(d_->window);
  d_->window->AddRenderer(d_->renderer);
  d_->renderer->SetBackground(0.08, 0.09, 0.11);
  split->addWidget(d_->widget);
  auto* right = new QSplitter(Qt::Vertical);
  d_->image = new QLabel;
  d_->image->setObjectName("scanImage");
  d_->image->setAlignment(Qt::AlignCenter);
  d_->image->setMinimumSize(320, 100);
  d_->image->installEventFilter(this);
  d_->image->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
  right->addWidget(d_->image);
  d_->counts = new QTableWidget(0, 2);
  d_->counts->setObjectName("scanCounts");
  d_->counts->setHorizontalHeaderLabels({"class", "points"});
  d_->counts->horizontalHeader()->setStretchLastSection(true);
  d_->counts->verticalHeader()->hide();
  d_->counts->setEditTriggers(QAbstractItemView::NoEditTriggers);
  right->addWidget(d_->counts);
  split->addWidget(right);
  right->setStretchFactor(0, 2);
  right->setStretchFactor(1, 1);
  split->setStretchFactor(0, 1);
  split->setStretchFactor(1, 1);
  layout->addWidget(split, 1);
  d_->status = new QLabel("Open a dataset (File ▸ Open dataset) or run one to see its scans.");
  d_->status->setObjectName("scanStatus");
  layout->addWidget(d_->status);

  // The scan: one vertex cell per point, coloured per point; float relative to the sensor, as
  // the .bin holds it.
  d_->colours->SetNumberOfComponents(3);
  d_->colours->SetName("colour");
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(d_->cloud);
  mapper->SetColorModeToDirectScalars();
  mapper->SetScalarModeToUsePointData();
  d_->actor->SetMapper(mapper);
  d_->actor->GetProperty()->SetPointSize(2.0);
  d_->renderer->AddActor(d_->actor);

  connect(d_->frame_spin, qOverload<int>(&QSpinBox::valueChanged), this, &ScanView::setFrame);
  connect(d_->frame_slider, &QSlider::valueChanged, this, &ScanView::setFrame);
  connect(d_->lidar_box, qOverload<int>(&QComboBox::currentIndexChanged), this,
          &ScanView::setLidar);
  connect(d_->camera_box, qOverload<int>(&QComboBox::currentIndexChanged), this,
          &ScanView::setCamera);
  connect(d_->colour_box, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [this](int i) { setColour(static_cast<Colour>(std::max(0, i))); });
  connect(d_->picture_box, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [this](int i) { setPicture(static_cast<Picture>(std::max(0, i))); });
  connect(d_->overlay_box, &QCheckBox::toggled, this, &ScanView::setOverlay);
}

ScanView::~ScanView() = default;

bool ScanView::setDataset(const QString& root) {
  const io::Manifest manifest = io::Manifest::read(root.toStdString());
  const QDir sequence(QDir(root).filePath(QString::fromStdString(manifest.sequence_dir)));
  d_->sequence = sequence.absolutePath();
  d_->lidars = lidarFolders(sequence);
  d_->cameras = cameraFolders(sequence);
  d_->frames = static_cast<int>(manifest.frames);
  d_->calib.clear();
  d_->overlay_problem.clear();
  if (!d_->lidars.isEmpty() && !d_->cameras.isEmpty()) {
    const std::string calib =
        sequence.filePath(QString::fromUtf8(io::DatasetLayout::kCalib)).toStdString();
    try {
      d_->calib = io::parseKittiCalib(io::readFile(calib), calib);
    } catch (const std::exception& e) {
      d_->overlay_problem = QString::fromUtf8(e.what());
    }
  }
  d_->instances =
      readInstances(sequence.filePath(QString::fromUtf8(io::DatasetLayout::kInstances)));
  d_->pixel_images = {};
  d_->frame = d_->lidar = d_->camera = 0;
  d_->camera_placed = false;
  for (QComboBox* box : {d_->lidar_box, d_->camera_box})
    box->blockSignals(true);
  d_->lidar_box->clear();
  d_->lidar_box->addItems(d_->lidars);
  d_->camera_box->clear();
  d_->camera_box->addItems(d_->cameras);
  for (QComboBox* box : {d_->lidar_box, d_->camera_box})
    box->blockSignals(false);
  showFrameControls();
  updateProjection();
  loadScan();
  loadPicture();
  if (d_->lidars.isEmpty() && d_->cameras.isEmpty()) {
    d_->status->setText(root + " has no LiDAR scans or camera images.");
    return false;
  }
  return true;
}

void ScanView::showFrameControls() {
  const int last = std::max(0, d_->frames - 1);
  for (QWidget* w :
       {static_cast<QWidget*>(d_->frame_spin), static_cast<QWidget*>(d_->frame_slider)})
    w->blockSignals(true);
  d_->frame_spin->setRange(0, last);
  d_->frame_slider->setRange(0, last);
  d_->frame_spin->setValue(d_->frame);
  d_->frame_slider->setValue(d_->frame);
  for (QWidget* w :
       {static_cast<QWidget*>(d_->frame_spin), static_cast<QWidget*>(d_->frame_slider)})
    w->blockSignals(false);
}

void ScanView::setFrame(int frame) {
  d_->frame = std::clamp(frame, 0, std::max(0, d_->frames - 1));
  showFrameControls();
  if (d_->sequence.isEmpty())
    return;
  loadScan();
  loadPicture();
}

void ScanView::setLidar(int index) {
  d_->lidar = std::clamp(index, 0, std::max(0, static_cast<int>(d_->lidars.size()) - 1));
  updateProjection();
  if (!d_->sequence.isEmpty())
    loadScan();
}

void ScanView::setCamera(int index) {
  d_->camera = std::clamp(index, 0, std::max(0, static_cast<int>(d_->cameras.size()) - 1));
  updateProjection();
  if (!d_->sequence.isEmpty())
    loadPicture();
}

void ScanView::setColour(Colour colour) {
  d_->colour = colour;
  d_->colour_box->blockSignals(true);
  d_->colour_box->setCurrentIndex(static_cast<int>(colour));
  d_->colour_box->blockSignals(false);
  recolour();
}

void ScanView::setPicture(Picture picture) {
  d_->picture_kind = picture;
  d_->picture_box->blockSignals(true);
  d_->picture_box->setCurrentIndex(static_cast<int>(picture));
  d_->picture_box->blockSignals(false);
  if (!d_->sequence.isEmpty())
    loadPicture();
}

void ScanView::setOverlay(bool on) {
  d_->overlay = on;
  d_->overlay_box->blockSignals(true);
  d_->overlay_box->setChecked(on);
  d_->overlay_box->blockSignals(false);
  composePicture();
}

// The shown pair's projection; a calib.txt that could not be read keeps its problem.
void ScanView::updateProjection() {
  d_->projection.reset();
  if (d_->calib.empty())
    return;
  d_->overlay_problem.clear();
  d_->projection = pairProjection(d_->calib, d_->lidar, d_->camera, d_->overlay_problem);
}

QString ScanView::frameFile(const std::string& folder, const char* extension) const {
  return QDir(d_->sequence)
      .filePath(QString::fromStdString(io::DatasetLayout::frameFile(folder, d_->frame, extension)));
}

// Reads the frame's scan: its points, and the labels when the .label is there. A file that
// cannot be read, or a .label without one word per point of the .bin, leaves the scan empty and
// says so in the status line.
void ScanView::loadScan() {
  d_->xyzi.clear();
  d_->labels.clear();
  d_->scan_problem.clear();
  d_->unit_intensity = true;
  if (!d_->lidars.isEmpty()) {
    const QString bin = frameFile(io::DatasetLayout::velodyneFolder(d_->lidar), "bin");
    const QString label = frameFile(io::DatasetLayout::labelsFolder(d_->lidar), "label");
    try {
      const std::string points = io::readFile(bin.toStdString());
      if (points.size() % 16 != 0)
        throw IoError(bin.toStdString() + ": not a whole number of 16-byte points");
      d_->xyzi.resize(points.size() / 4);
      std::memcpy(d_->xyzi.data(), points.data(), points.size());
      if (QFileInfo::exists(label)) {
        const std::string words = io::readFile(label.toStdString());
        if (words.size() != points.size() / 4)
          throw IoError(label.toStdString() + ": " + std::to_string(words.size() / 4) +
                        " labels for " + std::to_string(points.size() / 16) + " points");
        d_->labels.resize(words.size() / 4);
        std::memcpy(d_->labels.data(), words.data(), words.size());
      } else {
        d_->scan_problem = label + " is missing: every point shown as unlabelled";
      }
    } catch (const std::exception& e) {
      d_->xyzi.clear();
      d_->labels.clear();
      d_->scan_problem = QString::fromUtf8(e.what());
    }
  }
  // KITTI's 0..1 reflectance, or the VLP-16 scale's 0..255 (sensors.lidars[].scale).
  for (std::size_t i = 3; i < d_->xyzi.size() && d_->unit_intensity; i += 4)
    d_->unit_intensity = d_->xyzi[i] <= 1.0f;

  // The geometry, once per scan (a colour change only recolours it).
  const std::size_t n = d_->xyzi.size() / 4;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  vtkNew<vtkCellArray> verts;
  verts->AllocateExact(static_cast<vtkIdType>(n), static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &d_->xyzi[4 * i];
    points->SetPoint(static_cast<vtkIdType>(i), p[0], p[1], p[2]);
    const vtkIdType id = static_cast<vtkIdType>(i);
    verts->InsertNextCell(1, &id);
  }
  d_->cloud->SetPoints(points);
  d_->cloud->SetVerts(verts);

  // The points per class, most first.
  std::map<int, int> counts = classCounts();
  std::vector<std::pair<int, int>> rows(counts.begin(), counts.end());
  std::sort(rows.begin(), rows.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  d_->counts->setRowCount(static_cast<int>(rows.size()));
  const auto table = scene::classes();
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const auto [id, points_of_class] = rows[static_cast<std::size_t>(r)];
    const QString name = id < static_cast<int>(table.size())
                             ? QString::fromStdString(table[static_cast<std::size_t>(id)].name)
                             : QString("unknown id %1").arg(id);
    auto* item = new QTableWidgetItem(name);
    const Rgb c = classColour(static_cast<std::uint32_t>(id));
    QPixmap swatch(12, 12);
    swatch.fill(QColor(c[0], c[1], c[2]));
    item->setIcon(QIcon(swatch));
    d_->counts->setItem(r, 0, item);
    d_->counts->setItem(r, 1, new QTableWidgetItem(QString::number(points_of_class)));
  }
  recolour();
}

// Reads the frame's picture of the chosen kind, in colours people can read.
void ScanView::loadPicture() {
  d_->base = QImage();
  d_->picture_problem.clear();
  d_->pixel.clear();
  if (!d_->cameras.isEmpty()) {
    const std::string folder[] = {
        io::DatasetLayout::imageFolder(d_->camera), io::DatasetLayout::semanticFolder(d_->camera),
        io::DatasetLayout::depthFolder(d_->camera), io::DatasetLayout::instanceFolder(d_->camera)};
    const QString path = frameFile(folder[static_cast<int>(d_->picture_kind)], "png");
    try {
      const io::PngImage png = io::decodePng(io::readFile(path.toStdString()));
      QImage img(png.width, png.height, QImage::Format_RGB888);
      for (int v = 0; v < png.height; ++v) {
        std::uint8_t* row = img.scanLine(v);
        for (int u = 0; u < png.width; ++u) {
          const std::size_t i = static_cast<std::size_t>(v) * png.width + u;
          Rgb c{};
          if (png.channels == 3 && png.depth == 8)
            for (std::size_t k = 0; k < 3; ++k)
              c[k] = static_cast<std::uint8_t>(png.samples8[3 * i + k]);
          else if (d_->picture_kind == Picture::kSemantic && png.depth == 8)
            c = classColour(static_cast<std::uint8_t>(png.samples8[i]));
          else if (d_->picture_kind == Picture::kDepth && png.depth == 16) {
            // KITTI depth: metres × 256, 0 = nothing; near bright, 80 m and beyond dark.
            const double m = png.samples16[i] / 256.0;
            c = png.samples16[i] == 0 ? Rgb{0, 0, 0} : ramp(1.0 - std::min(m, 80.0) / 80.0);
          } else if (d_->picture_kind == Picture::kInstance && png.depth == 16)
            c = instanceColour(png.samples16[i]);
          else
            throw IoError(path.toStdString() + ": not the PNG this picture needs");
          std::memcpy(row + 3 * u, c.data(), 3);
        }
      }
      d_->base = img;
    } catch (const std::exception& e) {
      d_->picture_problem = QString::fromUtf8(e.what());
    }
  }
  composePicture();
}

// The picture, with the scan's points drawn on it when asked: squares of a few pixels in the
// points' colours, far points first so that near ones stay on top.
void ScanView::composePicture() {
  d_->picture = d_->base;
  if (d_->overlay && !d_->picture.isNull()) {
    QImage& img = d_->picture;
    const int r = std::max(1, img.width() / 800);
    for (const Projected& p : projected()) {
      const Rgb c = pointColour(p.point);
      const int u0 = static_cast<int>(std::lround(p.u)), v0 = static_cast<int>(std::lround(p.v));
      for (int v = std::max(0, v0 - r); v <= std::min(img.height() - 1, v0 + r); ++v) {
        std::uint8_t* row = img.scanLine(v);
        for (int u = std::max(0, u0 - r); u <= std::min(img.width() - 1, u0 + r); ++u)
          std::memcpy(row + 3 * u, c.data(), 3);
      }
    }
  }
  showPicture();
  showStatus();
}

std::vector<ScanView::Projected> ScanView::projected() const {
  std::vector<Projected> out;
  if (!d_->projection || d_->base.isNull())
    return out;
  const std::size_t n = d_->xyzi.size() / 4;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &d_->xyzi[4 * i];
    if (const auto px = d_->projection->project(Eigen::Vector3d(p[0], p[1], p[2]), d_->base.width(),
                                                d_->base.height()))
      out.push_back({px->x(), px->y(), px->z(), static_cast<int>(i)});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Projected& a, const Projected& b) { return a.depth > b.depth; });
  return out;
}

void ScanView::showStatus() {
  QString text = QString("frame %1 (0 to %2)").arg(d_->frame).arg(std::max(0, d_->frames - 1));
  if (!d_->lidars.isEmpty())
    text += QString(", %1 points").arg(pointCount());
  QStringList problems{d_->scan_problem, d_->picture_problem};
  if (d_->overlay)
    problems << d_->overlay_problem;
  for (const QString& problem : problems)
    if (!problem.isEmpty())
      text += " — " + problem;
  if (!d_->pixel.isEmpty())
    text += " — " + d_->pixel;
  d_->status->setText(text);
}

void ScanView::recolour() {
  const std::size_t n = d_->xyzi.size() / 4;
  d_->colours->SetNumberOfTuples(static_cast<vtkIdType>(n));
  float z_lo = 1e30f, z_hi = -1e30f;
  for (std::size_t i = 0; i < n; ++i) {
    z_lo = std::min(z_lo, d_->xyzi[4 * i + 2]);
    z_hi = std::max(z_hi, d_->xyzi[4 * i + 2]);
  }
  const double intensity_scale = d_->unit_intensity ? 1.0 : 1.0 / 255.0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &d_->xyzi[4 * i];
    const std::uint32_t label = d_->labels.empty() ? 0u : d_->labels[i];
    Rgb c{};
    switch (d_->colour) {
      case Colour::kClass:
        c = classColour(label & 0xFFFFu);
        break;
      case Colour::kInstance:
        c = instanceColour(label >> 16);
        break;
      case Colour::kIntensity:
        c = ramp(p[3] * intensity_scale);
        break;
      case Colour::kHeight:
        c = ramp(z_hi > z_lo ? (p[2] - z_lo) / (z_hi - z_lo) : 0.0);
        break;
    }
    d_->colours->SetTypedTuple(static_cast<vtkIdType>(i), c.data());
  }
  d_->colours->Modified();
  d_->cloud->GetPointData()->SetScalars(d_->colours);
  d_->cloud->Modified();
  if (d_->overlay)
    composePicture();
  if (!d_->camera_placed && n > 0) {
    // From behind and above the sensor, looking ahead (KITTI's velodyne axes: x forward, z up).
    vtkCamera* cam = d_->renderer->GetActiveCamera();
    cam->SetPosition(-35.0, 0.0, 22.0);
    cam->SetFocalPoint(25.0, 0.0, 0.0);
    cam->SetViewUp(0.0, 0.0, 1.0);
    d_->renderer->ResetCameraClippingRange();
    d_->camera_placed = true;
  }
  showStatus();
  d_->window->Render();
}

void ScanView::showPicture() {
  if (d_->picture.isNull()) {
    d_->image->setPixmap(QPixmap());
    d_->image->setText(d_->cameras.isEmpty() ? "no camera" : "no picture");
    return;
  }
  d_->image->setPixmap(
      QPixmap::fromImage(d_->picture)
          .scaled(d_->image->size(), Qt::KeepAspectRatio, Qt::SmoothTransformation));
}

bool ScanView::eventFilter(QObject* watched, QEvent* event) {
  if (watched == d_->image && event->type() == QEvent::Resize)
    showPicture();  // the picture follows its pane when the splitters move
  if (watched == d_->image && event->type() == QEvent::MouseButtonPress && !d_->picture.isNull()) {
    // From the label's point to the picture's pixel: the picture is scaled to fit, centred.
    const QSize shown = d_->picture.size().scaled(d_->image->size(), Qt::KeepAspectRatio);
    const QPointF at = static_cast<QMouseEvent*>(event)->localPos() -
                       QPointF((d_->image->width() - shown.width()) / 2.0,
                               (d_->image->height() - shown.height()) / 2.0);
    const double scale = static_cast<double>(d_->picture.width()) / shown.width();
    d_->pixel = describePixel(static_cast<int>(std::floor(at.x() * scale)),
                              static_cast<int>(std::floor(at.y() * scale)));
    showStatus();
  }
  return QWidget::eventFilter(watched, event);
}

QString ScanView::describePixel(int u, int v) const {
  if (d_->cameras.isEmpty() || d_->picture.isNull() || u < 0 || v < 0 || u >= d_->picture.width() ||
      v >= d_->picture.height())
    return {};
  PixelImages& images = d_->pixel_images;
  if (images.frame != d_->frame || images.camera != d_->camera) {
    images = {d_->frame, d_->camera,
              readPng(frameFile(io::DatasetLayout::semanticFolder(d_->camera), "png")),
              readPng(frameFile(io::DatasetLayout::instanceFolder(d_->camera), "png")),
              readPng(frameFile(io::DatasetLayout::depthFolder(d_->camera), "png"))};
  }
  const auto sample = [&](const std::optional<io::PngImage>& png,
                          int depth) -> std::optional<std::uint32_t> {
    if (!png || png->width != d_->picture.width() || png->height != d_->picture.height() ||
        png->channels != 1 || png->depth != depth)
      return std::nullopt;
    const std::size_t i = static_cast<std::size_t>(v) * png->width + u;
    return depth == 8 ? png->samples8[i] : png->samples16[i];
  };
  QStringList parts;
  if (const auto cls = sample(images.semantic, 8)) {
    const auto& classes = scene::classes();
    parts << (*cls < classes.size() ? QString::fromStdString(classes[*cls].name)
                                    : QString("class %1").arg(*cls));
  }
  if (const auto id = sample(images.instance, 16); id && *id != 0) {
    QString text = QString("instance %1").arg(*id);
    if (const auto row = d_->instances.find(static_cast<int>(*id)); row != d_->instances.end()) {
      QStringList about;
      if (!row->second.track.isEmpty())
        about << "track " + row->second.track;
      if (!row->second.state.isEmpty())
        about << row->second.state;
      if (!about.isEmpty())
        text += " (" + about.join(", ") + ")";
    }
    parts << text;
  }
  if (const auto depth = sample(images.depth, 16))
    parts << (*depth == 0 ? QString("no depth")
                          : QString("%1 m").arg(*depth / 256.0, 0, 'f', 2));  // KITTI: m × 256
  return QString("pixel (%1, %2)").arg(u).arg(v) + (parts.isEmpty() ? "" : ": " + parts.join(", "));
}

int ScanView::frameCount() const {
  return d_->frames;
}
int ScanView::frame() const {
  return d_->frame;
}
QStringList ScanView::lidars() const {
  return d_->lidars;
}
QStringList ScanView::cameras() const {
  return d_->cameras;
}
int ScanView::pointCount() const {
  return static_cast<int>(d_->xyzi.size() / 4);
}

std::array<std::uint8_t, 3> ScanView::pointColour(int i) const {
  Rgb c{};
  d_->colours->GetTypedTuple(i, c.data());
  return c;
}

std::map<int, int> ScanView::classCounts() const {
  std::map<int, int> counts;
  for (const std::uint32_t label : d_->labels)
    ++counts[static_cast<int>(label & 0xFFFFu)];
  return counts;
}

QImage ScanView::picture() const {
  return d_->picture;
}
QString ScanView::status() const {
  return d_->status->text();
}

QImage ScanView::grabImage() {
  d_->window->Render();
  return d_->widget->grabFramebuffer();
}

}  // namespace trainsim::studio
