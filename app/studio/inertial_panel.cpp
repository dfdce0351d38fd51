#include "inertial_panel.hpp"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "trainsim/core/frames.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/sim/sensor_params.hpp"

namespace trainsim::studio {
namespace {

const QString kTrajectoryTime = "Trajectory over time";
const QString kTrajectoryChainage = "Trajectory over chainage";
const QColor kMeasured(31, 119, 180);
const QColor kTruth(20, 20, 20);
const QColor kColours[3] = {QColor(214, 39, 40), QColor(44, 160, 44), QColor(31, 119, 180)};

QVector<double> seconds(const QVector<double>& t_ns) {
  QVector<double> out(t_ns.size());
  std::transform(t_ns.begin(), t_ns.end(), out.begin(), [](double t) { return t * 1e-9; });
  return out;
}

QVector<double> toQ(const std::vector<double>& v) {
  return QVector<double>(v.begin(), v.end());
}

// Row index in trajectory.csv of a time, from the trajectory's fixed period.
int truthRow(const CsvTable& truth, double t_ns) {
  const QVector<double>& t = truth.at("t_ns");
  const double period = t.size() > 1 ? t[1] - t[0] : 1.0;
  return std::clamp(static_cast<int>(std::llround(t_ns / period)), 0, truth.rows - 1);
}

const scenario::Json* sensorConfig(const scenario::Json& sc, const char* kind,
                                   const std::string& name) {
  for (const scenario::Json& s : sc["sensors"][kind]) {
    if (s["name"] == name)
      return &s;
  }
  return nullptr;
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
  DatasetFiles files = findDatasetFiles(root);
  std::map<QString, CsvTable> tables;
  tables.emplace("trajectory.csv", readCsv(root + "/trajectory.csv"));  // the truth
  dataset_ = std::move(files);
  tables_ = std::move(tables);
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
  // Each entry carries the sensor's name as item data.
  std::vector<std::pair<QString, QString>> entries{{kTrajectoryTime, {}},
                                                   {kTrajectoryChainage, {}}};
  if (dataset_) {
    for (const auto& [name, file] : dataset_->imus) {
      const QString n = QString::fromStdString(name);
      entries.emplace_back("IMU " + n + ": accelerometer vs truth", n);
      entries.emplace_back("IMU " + n + ": gyroscope vs truth", n);
    }
    for (const auto& [name, file] : dataset_->gnss)
      entries.emplace_back("GNSS " + QString::fromStdString(name) + ": error vs truth",
                           QString::fromStdString(name));
    for (const auto& [name, file] : dataset_->odometers)
      entries.emplace_back("Odometer " + QString::fromStdString(name) + " vs truth",
                           QString::fromStdString(name));
    for (const auto& [name, file] : dataset_->balises)
      entries.emplace_back("Balises " + QString::fromStdString(name) + " vs truth",
                           QString::fromStdString(name));
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
      rows = {{"speed [m/s]", {{"speed", x, toQ(s.speed_m_s), kMeasured}}},
              {"acceleration [m/s²]", {{"along track", x, toQ(s.accel_m_s2), kMeasured}}},
              {"angular rate [rad/s]",
               {{"roll rate", x, toQ(s.roll_rate), kColours[0]},
                {"pitch rate", x, toQ(s.pitch_rate), kColours[1]},
                {"yaw rate", x, toQ(s.yaw_rate), kColours[2]}}},
              {"curvature [1/m]", {{"curvature", x, toQ(s.curvature_1_m), kMeasured}}}};
      note_->setText(
          QString("planned run: %1 s, %2 km (ground truth, body axes)")
              .arg(plan_->duration_s, 0, 'f', 1)
              .arg(s.chainage_m.empty() ? 0.0 : s.chainage_m.back() / 1000.0, 0, 'f', 2));
    } else if (dataset_) {
      const std::string name = view_->currentData().toString().toStdString();
      if (v.startsWith("IMU "))
        rows = imuRows(name, v.contains("gyroscope"));
      else if (v.startsWith("GNSS "))
        rows = gnssRows(name);
      else if (v.startsWith("Odometer "))
        rows = odometerRows(name);
      else if (v.startsWith("Balises "))
        rows = baliseRows(name);
      note_->setText("dataset " + dataset_->root);
    }
  } catch (const std::exception& e) {
    note_->setText(QString("cannot show %1: %2").arg(v, QString::fromUtf8(e.what())));
    rows.clear();
  }
  plots_->setRows(x_label, rows);
}

const CsvTable& InertialPanel::table(const QString& path) const {
  auto it = tables_.find(path);
  if (it == tables_.end())
    it = tables_.emplace(path, readCsv(path)).first;
  return it->second;
}

std::vector<PlotRow> InertialPanel::imuRows(const std::string& name, bool gyro) const {
  const QString file = dataset_->imus.at(name);
  const CsvTable& m = table(file);
  const CsvTable& t = table(QString(file).replace(".csv", "_truth.csv"));
  const QVector<double> tm = seconds(m.at("t_ns")), tt = seconds(t.at("t_ns"));
  std::vector<PlotRow> rows;
  for (const char axis : {'x', 'y', 'z'}) {
    const std::string measured =
        gyro ? std::string("w") + axis + "_rad_s" : std::string("a") + axis + "_m_s2";
    const std::string truth =
        gyro ? std::string("w") + axis + "_rad_s" : std::string("f") + axis + "_m_s2";
    rows.push_back({QString::fromStdString(measured),
                    {{QString::fromStdString(name + " " + measured), tm, m.at(measured), kMeasured},
                     {QString::fromStdString("truth " + truth), tt, t.at(truth), kTruth}}});
  }
  return rows;
}

std::vector<PlotRow> InertialPanel::gnssRows(const std::string& name) const {
  const CsvTable& g = table(dataset_->gnss.at(name));
  const scenario::Json& sc = dataset_->scenario;
  const scenario::Json* cfg = sensorConfig(sc, "gnss_receivers", name);
  const Eigen::Vector3d antenna = cfg ? sim::readMount(*cfg).position_m : Eigen::Vector3d::Zero();
  const GeodeticAnchor anchor = sim::geodeticAnchor(sc);
  const CsvTable& tr = tables_.at("trajectory.csv");
  QVector<double> t, de, dn, du, fix;
  for (int i = 0; i < g.rows; ++i) {
    const double t_ns = g.at("t_ns")[i];
    t.push_back(t_ns * 1e-9);
    fix.push_back(g.at("fix")[i]);
    if (g.at("fix")[i] == 0.0) {  // no fix: a gap in the error lines
      de.push_back(NAN);
      dn.push_back(NAN);
      du.push_back(NAN);
      continue;
    }
    const int k = truthRow(tr, t_ns);
    const Eigen::Vector3d p(tr.at("x_m")[k], tr.at("y_m")[k], tr.at("z_m")[k]);
    const Eigen::Vector3d truth =
        p + attitude(tr.at("yaw_rad")[k], tr.at("pitch_rad")[k], tr.at("roll_rad")[k]) * antenna;
    const Eigen::Vector3d fixed =
        anchor.toEnu({g.at("latitude_deg")[i], g.at("longitude_deg")[i], g.at("height_m")[i]});
    de.push_back(fixed.x() - truth.x());
    dn.push_back(fixed.y() - truth.y());
    du.push_back(fixed.z() - truth.z());
  }
  return {{"east error [m]", {{"fix − truth, east", t, de, kColours[0]}}},
          {"north error [m]", {{"fix − truth, north", t, dn, kColours[1]}}},
          {"up error [m]", {{"fix − truth, up", t, du, kColours[2]}}},
          {"fix", {{"fix (0: none)", t, fix, kMeasured}}}};
}

std::vector<PlotRow> InertialPanel::odometerRows(const std::string& name) const {
  const CsvTable& o = table(dataset_->odometers.at(name));
  const CsvTable& tr = tables_.at("trajectory.csv");
  const QVector<double> t = seconds(o.at("t_ns"));
  QVector<double> distance, speed;
  for (int i = 0; i < o.rows; ++i) {
    const int k = truthRow(tr, o.at("t_ns")[i]);
    distance.push_back(tr.at("distance_m")[k]);
    speed.push_back(tr.at("speed_m_s")[k]);
  }
  QVector<double> error(o.rows);
  for (int i = 0; i < o.rows; ++i)
    error[i] = o.at("distance_m")[i] - distance[i];
  return {{"distance [m]",
           {{QString::fromStdString(name + " distance"), t, o.at("distance_m"), kMeasured},
            {"truth distance", t, distance, kTruth}}},
          {"distance error [m]", {{"odometer − truth", t, error, kColours[0]}}},
          {"speed [m/s]",
           {{QString::fromStdString(name + " speed"), t, o.at("speed_m_s"), kMeasured},
            {"truth speed", t, speed, kTruth}}},
          {"slip (1) / slide (−1)", {{"slip", t, o.at("slip"), kColours[1]}}}};
}

std::vector<PlotRow> InertialPanel::baliseRows(const std::string& name) const {
  const CsvTable& b = table(dataset_->balises.at(name));
  const CsvTable& tr = tables_.at("trajectory.csv");
  const scenario::Json* cfg = sensorConfig(dataset_->scenario, "balise_readers", name);
  const double offset =
      cfg ? sim::aheadOfFrontPivot(dataset_->scenario, sim::readMount(*cfg)) : 0.0;
  QVector<double> t_truth = seconds(tr.at("t_ns")), antenna = tr.at("distance_m");
  for (double& d : antenna)
    d += offset;
  QVector<double> error(b.rows);
  for (int i = 0; i < b.rows; ++i) {
    // The antenna's true distance at the event time, linearly interpolated between samples.
    const double t_ns = b.at("t_ns")[i];
    const int k = std::min(truthRow(tr, t_ns), tr.rows - 2);
    const QVector<double>& tt = tr.at("t_ns");
    const int k0 = tt[k] > t_ns && k > 0 ? k - 1 : k;
    const double w = (t_ns - tt[k0]) / (tt[k0 + 1] - tt[k0]);
    error[i] = b.at("position_m")[i] - (antenna[k0] + w * (antenna[k0 + 1] - antenna[k0]));
  }
  return {{"distance along track [m]",
           {{"reader antenna (truth)", t_truth, antenna, kTruth},
            {QString::fromStdString(name + " events"), seconds(b.at("t_ns")), b.at("position_m"),
             kColours[0], true}}},
          {"event position − truth [m]",
           {{"balise position − antenna", seconds(b.at("t_ns")), error, kColours[0], true}}}};
}

}  // namespace trainsim::studio
