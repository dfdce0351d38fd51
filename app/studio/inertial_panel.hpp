#pragma once

#include <QWidget>
#include <memory>
#include <optional>

#include "dataset_series.hpp"
#include "plan_service.hpp"
#include "plot_panel.hpp"
#include "sensor_views.hpp"

class QComboBox;
class QLabel;

namespace trainsim::studio {

/// Inertial panels: the planned trajectory (speed, acceleration, angular rate, curvature over
/// time or chainage) and, once a dataset exists, the views registered for each of its sensors'
/// kinds (sensor_views.hpp: IMU, GNSS, odometer and balise reader against the ground truth).
/// Selecting a time emits timeSelected, which the design views use to place the train.
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

  QComboBox* view_;
  QLabel* note_;
  PlotPanel* plots_;
  std::shared_ptr<const PlanSnapshot> plan_;
  std::unique_ptr<DatasetFiles> dataset_;
  std::unique_ptr<DatasetTables> tables_;  // reads each CSV once per dataset
};

}  // namespace trainsim::studio
