#pragma once

#include <QWidget>
#include <memory>
#include <optional>

#include "dataset_series.hpp"
#include "plan_service.hpp"
#include "plot_panel.hpp"

class QComboBox;
class QLabel;

namespace trainsim::studio {

/// Inertial panels: the planned trajectory (speed, acceleration, angular rate, curvature over
/// time or chainage) and, once a dataset exists, each simulated IMU, GNSS receiver, odometer
/// and balise reader against the ground truth written with it (trajectory.csv and the
/// <imu>_truth.csv files). Selecting a time emits timeSelected, which the design views use to
/// place the train.
class InertialPanel : public QWidget {
  Q_OBJECT

 public:
  explicit InertialPanel(QWidget* parent = nullptr);

  void setPlan(std::shared_ptr<const PlanSnapshot> plan);
  /// Loads the sensor files of a dataset folder; throws IoError/ConfigError naming the file.
  void setDataset(const QString& root);

  /// The views on offer ("Trajectory over time", "IMU imu: accelerometer", ...).
  QStringList views() const;
  void showView(const QString& name);
  QString currentView() const;
  PlotPanel* plots() const { return plots_; }

 signals:
  /// A time (s since the start of the run) was selected in a plot.
  void timeSelected(double t_s);

 private:
  void refreshViews();
  void draw();
  std::vector<PlotRow> imuRows(const std::string& name, bool gyro) const;
  std::vector<PlotRow> gnssRows(const std::string& name) const;
  std::vector<PlotRow> odometerRows(const std::string& name) const;
  std::vector<PlotRow> baliseRows(const std::string& name) const;
  /// A dataset CSV, read once per dataset (switching views does not read files again).
  const CsvTable& table(const QString& path) const;

  QComboBox* view_;
  QLabel* note_;
  PlotPanel* plots_;
  std::shared_ptr<const PlanSnapshot> plan_;
  std::optional<DatasetFiles> dataset_;
  mutable std::map<QString, CsvTable> tables_;
};

}  // namespace trainsim::studio
