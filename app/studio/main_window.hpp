#pragma once

#include <QMainWindow>
#include <memory>

#include "plan_service.hpp"
#include "run_controller.hpp"
#include "scenario_document.hpp"

class QLabel;
class QLineEdit;
class QProgressBar;
class QPushButton;
class QTableWidget;
class QTabWidget;

namespace trainsim::studio {

class DesignView3D;
class InertialPanel;
class PlanView2D;
class ScanView;
class SceneView;
class SchemaForm;

/// The studio's main window: the generated parameter panels on the left, the design views
/// (3D, plan and the planned scene) and a dataset's scans and pictures with their labels top right,
/// the inertial plots and the design report below them, run controls in the tool bar and status
/// bar.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Opens a scenario file. Unreadable or malformed files leave the current scenario in place;
  /// files with invalid values are loaded with the fields marked. Either way the validator's
  /// messages are shown in a (non-blocking) dialog. Returns true when the file was loaded.
  bool openScenario(const QString& path);
  /// Starts generating the dataset into `out`; returns false if the scenario is invalid or a
  /// run is going (with a message).
  bool startRun(const QString& out, bool force);
  /// Shows the sensor data of an existing dataset folder: the inertial panels, and its LiDAR
  /// scans and camera pictures in the scan view.
  bool openDataset(const QString& root);

  ScenarioDocument* document() { return &doc_; }
  SchemaForm* form() const { return form_; }
  DesignView3D* view3d() const { return view3d_; }
  PlanView2D* view2d() const { return view2d_; }
  InertialPanel* inertial() const { return inertial_; }
  ScanView* scans() const { return scans_; }
  SceneView* scene() const { return scene_; }
  QTabWidget* viewTabs() const { return views_; }
  QTableWidget* report() const { return report_; }
  QProgressBar* progressBar() const { return progress_; }
  RunController* runner() { return &runner_; }
  std::shared_ptr<const PlanSnapshot> plan() const { return plan_; }
  const PlanService& planService() const { return planner_; }

 signals:
  /// The views show a new plan.
  void planShown();

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void buildMenus();
  void onDocumentChanged();
  void onPlanned(std::shared_ptr<const PlanSnapshot> plan);
  void onRunFinished(int code, const QString& message, const QString& out);
  void showReport();
  void showMessage(const QString& title, const QString& text, const QString& details);
  void selectTime(double t_s);
  /// Offers to save unsaved edits; false when the user cancels.
  bool maybeSave();
  bool saveAs();
  bool save();
  void updateTitle();

  ScenarioDocument doc_;
  PlanService planner_;
  RunController runner_;
  std::shared_ptr<const PlanSnapshot> plan_;
  QString plan_error_;
  SchemaForm* form_ = nullptr;
  QTabWidget* views_ = nullptr;
  DesignView3D* view3d_ = nullptr;
  PlanView2D* view2d_ = nullptr;
  InertialPanel* inertial_ = nullptr;
  ScanView* scans_ = nullptr;
  SceneView* scene_ = nullptr;
  QTableWidget* report_ = nullptr;
  QLineEdit* out_dir_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QPushButton* cancel_ = nullptr;
  QLabel* status_ = nullptr;
};

}  // namespace trainsim::studio
