#pragma once

// The registry of views the studio offers for a dataset's sensors: one line per view, keyed
// by the sensor kind the manifest gives. The inertial panel lists, for every sensor of a
// dataset, each view registered for its kind; the coming point-cloud, image and terrain views
// register here the same way (with their own presenter beside `plot`).

#include <QString>
#include <functional>
#include <map>
#include <span>
#include <vector>

#include "dataset_series.hpp"
#include "plot_panel.hpp"

namespace trainsim::studio {

/// What a view may read of a dataset: its CSV files (read once, then cached) and the truth.
class DatasetTables {
 public:
  explicit DatasetTables(const DatasetFiles& dataset);
  const DatasetFiles& dataset() const { return dataset_; }
  /// A CSV of the dataset by absolute path.
  const CsvTable& table(const QString& path) const;
  /// OUT/trajectory.csv, the ground truth at T_S.
  const CsvTable& truth() const;

 private:
  const DatasetFiles& dataset_;
  mutable std::map<QString, CsvTable> tables_;
};

/// A view of one sensor: its title (with "%1" for the sensor's name) and how its plot rows are
/// made from the sensor's files and the truth.
struct SensorView {
  const char* kind;
  const char* title;
  std::function<std::vector<PlotRow>(const DatasetSensor&, const DatasetTables&)> plot;
};

/// The registered views, in menu order.
std::span<const SensorView> sensorViews();

}  // namespace trainsim::studio
