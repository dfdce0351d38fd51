#include "sensor_views.hpp"

#include <algorithm>
#include <cmath>

#include "trainsim/core/frames.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/sim/sensor_params.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::studio {
namespace {

// Row index in trajectory.csv of a time, from the trajectory's fixed period.
int truthRow(const CsvTable& truth, double t_ns) {
  const QVector<double>& t = truth.at("t_ns");
  const double period = t.size() > 1 ? t[1] - t[0] : 1.0;
  return std::clamp(static_cast<int>(std::llround(t_ns / period)), 0, truth.rows - 1);
}

std::vector<PlotRow> imuRows(const DatasetSensor& sensor, const DatasetTables& data, bool gyro) {
  const std::string& name = sensor.name;
  const CsvTable& m = data.table(sensor.files.value(0));
  const CsvTable& t = data.table(sensor.files.value(1));
  const QVector<double> tm = seconds(m.at("t_ns")), tt = seconds(t.at("t_ns"));
  std::vector<PlotRow> rows;
  for (const char axis : {'x', 'y', 'z'}) {
    const std::string measured =
        gyro ? std::string("w") + axis + "_rad_s" : std::string("a") + axis + "_m_s2";
    const std::string truth =
        gyro ? std::string("w") + axis + "_rad_s" : std::string("f") + axis + "_m_s2";
    rows.push_back(
        {QString::fromStdString(measured),
         {{QString::fromStdString(name + " " + measured), tm, m.at(measured), kMeasuredColour},
          {QString::fromStdString("truth " + truth), tt, t.at(truth), kTruthColour}}});
  }
  return rows;
}

std::vector<PlotRow> gnssRows(const DatasetSensor& sensor, const DatasetTables& data) {
  const CsvTable& g = data.table(sensor.files.value(0));
  const scenario::Json& sc = data.dataset().scenario;
  const Eigen::Vector3d antenna =
      sensor.config.is_null() ? Eigen::Vector3d::Zero() : sim::readMount(sensor.config).position_m;
  const GeodeticAnchor anchor = sim::geodeticAnchor(sc);
  const CsvTable& tr = data.truth();
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
    // yaw, pitch and roll are against the local level at the train (trajectory.csv), and the
    // errors are east/north/up there.
    const Eigen::Matrix3d r_world_local = anchor.rotationAnchorFromLocalEnu(p);
    const Eigen::Vector3d truth =
        p + r_world_local *
                attitude(tr.at("yaw_rad")[k], tr.at("pitch_rad")[k], tr.at("roll_rad")[k]) *
                antenna;
    const Eigen::Vector3d fixed =
        anchor.toEnu({g.at("latitude_deg")[i], g.at("longitude_deg")[i], g.at("height_m")[i]});
    const Eigen::Vector3d error = r_world_local.transpose() * (fixed - truth);
    de.push_back(error.x());
    dn.push_back(error.y());
    du.push_back(error.z());
  }
  return {{"east error [m]", {{"fix − truth, east", t, de, kAxisColours[0]}}},
          {"north error [m]", {{"fix − truth, north", t, dn, kAxisColours[1]}}},
          {"up error [m]", {{"fix − truth, up", t, du, kAxisColours[2]}}},
          {"fix", {{"fix (0: none)", t, fix, kMeasuredColour}}}};
}

std::vector<PlotRow> odometerRows(const DatasetSensor& sensor, const DatasetTables& data) {
  const std::string& name = sensor.name;
  const CsvTable& o = data.table(sensor.files.value(0));
  const CsvTable& tr = data.truth();
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
           {{QString::fromStdString(name + " distance"), t, o.at("distance_m"), kMeasuredColour},
            {"truth distance", t, distance, kTruthColour}}},
          {"distance error [m]", {{"odometer − truth", t, error, kAxisColours[0]}}},
          {"speed [m/s]",
           {{QString::fromStdString(name + " speed"), t, o.at("speed_m_s"), kMeasuredColour},
            {"truth speed", t, speed, kTruthColour}}},
          {"slip (1) / slide (−1)", {{"slip", t, o.at("slip"), kAxisColours[1]}}}};
}

std::vector<PlotRow> baliseRows(const DatasetSensor& sensor, const DatasetTables& data) {
  const std::string& name = sensor.name;
  const CsvTable& b = data.table(sensor.files.value(0));
  const CsvTable& tr = data.truth();
  const double offset =
      sensor.config.is_null()
          ? 0.0
          : sim::aheadOfFrontPivot(data.dataset().scenario, sim::readMount(sensor.config));
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
           {{"reader antenna (truth)", t_truth, antenna, kTruthColour},
            {QString::fromStdString(name + " events"), seconds(b.at("t_ns")), b.at("position_m"),
             kAxisColours[0], true}}},
          {"event position − truth [m]",
           {{"balise position − antenna", seconds(b.at("t_ns")), error, kAxisColours[0], true}}}};
}

// The registry: one line per view.
const SensorView kViews[] = {
    {sim::kImuKind, "IMU %1: accelerometer vs truth",
     [](const DatasetSensor& s, const DatasetTables& d) { return imuRows(s, d, false); }},
    {sim::kImuKind, "IMU %1: gyroscope vs truth",
     [](const DatasetSensor& s, const DatasetTables& d) { return imuRows(s, d, true); }},
    {sim::kGnssKind, "GNSS %1: error vs truth", gnssRows},
    {sim::kOdometerKind, "Odometer %1 vs truth", odometerRows},
    {sim::kBaliseReaderKind, "Balises %1 vs truth", baliseRows},
};

}  // namespace

DatasetTables::DatasetTables(const DatasetFiles& dataset) : dataset_(dataset) {}

const CsvTable& DatasetTables::table(const QString& path) const {
  auto it = tables_.find(path);
  if (it == tables_.end())
    it = tables_.emplace(path, readCsv(path)).first;
  return it->second;
}

const CsvTable& DatasetTables::truth() const {
  return table(dataset_.root + "/" + io::DatasetLayout::kTrajectory);
}

std::span<const SensorView> sensorViews() {
  return kViews;
}

}  // namespace trainsim::studio
