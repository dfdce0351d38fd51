#include "inertial_panel.hpp"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPoint>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

namespace trainsim::studio {
namespace {

const QString kTrajectoryTime = "Trajectory over time";
const QString kTrajectoryChainage = "Trajectory over chainage";
QVector<double> toQ(const std::vector<double>& v) {
  return QVector<double>(v.begin(), v.end());
}

}  // namespace

InertialPanel::InertialPanel(QWidget* parent)
    : QWidget(parent), view_(new QComboBox), note_(new QLabel), plots_(new PlotPanel) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  auto* bar = new QHBoxLayout;
  bar->addWidget(new QLabel("Show"));
  view_->setObjectName("inertialView");
  view_->setMinimumWidth(260);
  bar->addWidget(view_);
  note_->setStyleSheet("color: #555;");
  bar->addWidget(note_, 1);
  layout->addLayout(bar);
  layout->addWidget(plots_, 1);
  connect(view_, &QComboBox::currentTextChanged, this, [this] { draw(); });
  connect(plots_, &PlotPanel::xSelected, this, [this](double x) {
    if (view_->currentText() != kTrajectoryChainage) {
      emit timeSelected(x);
      return;
    }
    // Chainage to the first time the train is there.
    if (!plan_)
      return;
    const auto& c = plan_->series.chainage_m;
    const auto it = std::lower_bound(c.begin(), c.end(), x);
    const std::size_t i =
        std::min<std::size_t>(static_cast<std::size_t>(it - c.begin()), c.size() - 1);
    emit timeSelected(plan_->series.t_s[i]);
  });
  refreshViews();
}

void InertialPanel::setPlan(std::shared_ptr<const PlanSnapshot> plan) {
  plan_ = std::move(plan);
  if (view_->currentText().startsWith("Trajectory"))
    draw();
}

void InertialPanel::setDataset(const QString& root) {
  auto dataset = std::make_unique<DatasetFiles>(findDatasetFiles(root));
  auto tables = std::make_unique<DatasetTables>(*dataset);
  tables->truth();  // read now: a dataset without its truth is refused here, not in a view
  tables_ = std::move(tables);
  dataset_ = std::move(dataset);
  refreshViews();
  draw();
}

QStringList InertialPanel::views() const {
  QStringList out;
  for (int i = 0; i < view_->count(); ++i)
    out << view_->itemText(i);
  return out;
}

void InertialPanel::showView(const QString& name) {
  view_->setCurrentText(name);
  draw();
}

QString InertialPanel::currentView() const {
  return view_->currentText();
}

void InertialPanel::refreshViews() {
  const QString current = view_->currentText();
  // Each entry carries (sensor index, view index) as item data; the views come from the
  // registry, by the kind the manifest gives each sensor.
  std::vector<std::pair<QString, QPoint>> entries{{kTrajectoryTime, {-1, -1}},
                                                  {kTrajectoryChainage, {-1, -1}}};
  if (dataset_) {
    const std::span<const SensorView> views = sensorViews();
    for (std::size_t i = 0; i < dataset_->sensors.size(); ++i) {
      const DatasetSensor& sensor = dataset_->sensors[i];
      for (std::size_t j = 0; j < views.size(); ++j)
        if (sensor.kind == views[j].kind)
          entries.emplace_back(QString(views[j].title).arg(QString::fromStdString(sensor.name)),
                               QPoint(static_cast<int>(i), static_cast<int>(j)));
    }
  }
  const QSignalBlocker block(view_);
  view_->clear();
  bool keep = false;
  for (const auto& [text, name] : entries) {
    view_->addItem(text, name);
    keep = keep || text == current;
  }
  view_->setCurrentText(keep ? current : kTrajectoryTime);
}

void InertialPanel::draw() {
  const QString v = view_->currentText();
  std::vector<PlotRow> rows;
  QString x_label = "time [s]";
  try {
    if (v == kTrajectoryTime || v == kTrajectoryChainage) {
      if (!plan_) {
        note_->setText("planning…");
        plots_->setRows(x_label, {});
        return;
      }
      const TrajectorySeries& s = plan_->series;
      const bool by_chainage = v == kTrajectoryChainage;
      const QVector<double> x = toQ(by_chainage ? s.chainage_m : s.t_s);
      x_label = by_chainage ? "chainage [m]" : "time [s]";
      rows = {{"speed [m/s]", {{"speed", x, toQ(s.speed_m_s), kMeasuredColour}}},
              {"acceleration [m/s²]", {{"along track", x, toQ(s.accel_m_s2), kMeasuredColour}}},
              {"angular rate [rad/s]",
               {{"roll rate", x, toQ(s.roll_rate), kAxisColours[0]},
                {"pitch rate", x, toQ(s.pitch_rate), kAxisColours[1]},
                {"yaw rate", x, toQ(s.yaw_rate), kAxisColours[2]}}},
              {"curvature [1/m]", {{"curvature", x, toQ(s.curvature_1_m), kMeasuredColour}}}};
      note_->setText(
          QString("planned run: %1 s, %2 km (ground truth, body axes)")
              .arg(plan_->duration_s, 0, 'f', 1)
              .arg(s.chainage_m.empty() ? 0.0 : s.chainage_m.back() / 1000.0, 0, 'f', 2));
    } else if (dataset_) {
      const QPoint at = view_->currentData().toPoint();
      if (at.x() >= 0) {
        const SensorView& view = sensorViews()[static_cast<std::size_t>(at.y())];
        rows = view.plot(dataset_->sensors[static_cast<std::size_t>(at.x())], *tables_);
      }
      note_->setText("dataset " + dataset_->root);
    }
  } catch (const std::exception& e) {
    note_->setText(QString("cannot show %1: %2").arg(v, QString::fromUtf8(e.what())));
    rows.clear();
  }
  plots_->setRows(x_label, rows);
}

}  // namespace trainsim::studio
