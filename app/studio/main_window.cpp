#include "main_window.hpp"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QRandomGenerator>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>
#include <QTableWidget>
#include <QToolBar>

#include "design_view_3d.hpp"
#include "inertial_panel.hpp"
#include "plan_view_2d.hpp"
#include "scan_view.hpp"
#include "scene_view.hpp"
#include "schema_form.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::studio {
namespace {

// Scenario paths and names the menus edit, from the route section's binding.
template <typename Member>
std::string routePath(Member member) {
  return sim::routeSection().path(member);
}
std::string sourceName(sim::RouteSource source) {
  return std::string(nameOf(source));
}

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setObjectName("mainWindow");
  resize(1500, 920);

  form_ = new SchemaForm(sim::scenarioSchema().root(), &doc_);
  form_->setObjectName("schemaForm");
  form_->setMinimumWidth(380);

  views_ = new QTabWidget;
  views_->setObjectName("designViews");
  view3d_ = new DesignView3D;
  view2d_ = new PlanView2D;
  views_->addTab(view3d_, "3D design");
  views_->addTab(view2d_, "Plan");
  scene_ = new SceneView;
  scene_->setObjectName("sceneView");
  views_->addTab(scene_, "Scene");
  scans_ = new ScanView;
  scans_->setObjectName("scanView");
  views_->addTab(scans_, "Scans and pictures");

  inertial_ = new InertialPanel;
  inertial_->setObjectName("inertialPanel");
  report_ = new QTableWidget(0, 6);
  report_->setObjectName("designReport");
  report_->setHorizontalHeaderLabels(
      {"rule", "chainage [m]", "block", "value", "limit", "message"});
  report_->horizontalHeader()->setStretchLastSection(true);
  report_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  report_->setSelectionBehavior(QAbstractItemView::SelectRows);
  auto* lower = new QTabWidget;
  lower->setObjectName("lowerTabs");
  lower->addTab(inertial_, "Inertial");
  lower->addTab(report_, "Design report");

  auto* right = new QSplitter(Qt::Vertical);
  right->addWidget(views_);
  right->addWidget(lower);
  right->setStretchFactor(0, 1);
  right->setStretchFactor(1, 1);
  right->setSizes({440, 440});
  auto* split = new QSplitter(Qt::Horizontal);
  split->addWidget(form_);
  split->addWidget(right);
  split->setStretchFactor(0, 0);
  split->setStretchFactor(1, 1);
  split->setSizes({420, 1080});
  setCentralWidget(split);

  progress_ = new QProgressBar;
  progress_->setObjectName("runProgress");
  progress_->setRange(0, 1000);
  progress_->setMaximumWidth(260);
  progress_->setTextVisible(true);
  progress_->setFormat("idle");
  progress_->setValue(0);
  cancel_ = new QPushButton("Cancel");
  cancel_->setObjectName("cancelRun");
  cancel_->setEnabled(false);
  status_ = new QLabel;
  status_->setObjectName("statusText");
  statusBar()->addWidget(status_, 1);
  statusBar()->addPermanentWidget(progress_);
  statusBar()->addPermanentWidget(cancel_);
  connect(cancel_, &QPushButton::clicked, &runner_, &RunController::cancel);

  buildMenus();

  connect(&doc_, &ScenarioDocument::changed, this, [this] { onDocumentChanged(); });
  connect(&doc_, &ScenarioDocument::filePathChanged, this, [this] { updateTitle(); });
  connect(doc_.undoStack(), &QUndoStack::cleanChanged, this, [this] { updateTitle(); });
  connect(&planner_, &PlanService::started, this, [this] { status_->setText("planning…"); });
  connect(&planner_, &PlanService::planned, this, &MainWindow::onPlanned);
  connect(&planner_, &PlanService::failed, this, [this](const QString& message) {
    plan_error_ = message;
    status_->setText("the plan failed: " + message);
    showReport();
  });
  connect(&runner_, &RunController::progress, this, [this](double f, const QString& text) {
    progress_->setValue(static_cast<int>(f * 1000.0));
    progress_->setFormat(text);
  });
  connect(&runner_, &RunController::finished, this, &MainWindow::onRunFinished);
  connect(inertial_, &InertialPanel::timeSelected, this, &MainWindow::selectTime);
  updateTitle();
  onDocumentChanged();
}

MainWindow::~MainWindow() = default;

void MainWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction(
      "&New", this,
      [this] {
        if (maybeSave())
          doc_.newDefault();
      },
      QKeySequence::New);
  file->addAction(
      "&Open scenario…", this,
      [this] {
        if (!maybeSave())
          return;
        const QString f = QFileDialog::getOpenFileName(this, "Open scenario", doc_.baseDir(),
                                                       "Scenario (*.json);;All files (*)");
        if (!f.isEmpty())
          openScenario(f);
      },
      QKeySequence::Open);
  file->addAction(
      "&Save", this, [this] { save(); }, QKeySequence::Save);
  file->addAction(
      "Save &as…", this, [this] { saveAs(); }, QKeySequence::SaveAs);
  file->addSeparator();
  file->addAction("&Import waypoints…", this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Import waypoints", doc_.baseDir(),
                                                   "Waypoints (*.csv);;All files (*)");
    if (f.isEmpty())
      return;
    const QString rel = QDir(doc_.baseDir()).relativeFilePath(f);
    doc_.beginMacro("Import waypoints");
    doc_.setValue(routePath(&sim::RouteConfig::waypoints_file),
                  (rel.startsWith("..") ? f : rel).toStdString());
    doc_.setValue(routePath(&sim::RouteConfig::source), sourceName(sim::RouteSource::kWaypoints));
    doc_.endMacro();
  });
  QAction* exportAction = file->addAction("&Export dataset…", this, [this] {
    const QString dir =
        QFileDialog::getExistingDirectory(this, "Export dataset to", out_dir_->text());
    if (dir.isEmpty())
      return;
    out_dir_->setText(dir);
    startRun(dir, false);
  });
  file->addAction("Open &dataset…", this, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "Open dataset", out_dir_->text());
    if (!dir.isEmpty())
      openDataset(dir);
  });
  file->addSeparator();
  file->addAction("&Quit", this, &QWidget::close, QKeySequence::Quit);

  QMenu* edit = menuBar()->addMenu("&Edit");
  QAction* undo = doc_.undoStack()->createUndoAction(this, "&Undo");
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = doc_.undoStack()->createRedoAction(this, "&Redo");
  redo->setShortcut(QKeySequence::Redo);
  edit->addAction(undo);
  edit->addAction(redo);

  QMenu* route = menuBar()->addMenu("&Route");
  QAction* regenerate = route->addAction("Regenerate with a new &seed", this, [this] {
    doc_.beginMacro("Regenerate route");
    doc_.setValue(routePath(&sim::RouteConfig::source), sourceName(sim::RouteSource::kGenerated));
    doc_.setValue(scenario::seedParam().key, QRandomGenerator::global()->bounded(1, 1'000'000'000));
    doc_.endMacro();
  });
  QAction* asBlocks = route->addAction("Edit as &block list", this, [this] {
    if (!plan_)
      return;
    doc_.beginMacro("Edit route as block list");
    doc_.setValue(routePath(&sim::RouteConfig::blocks),
                  sim::blockListJson(plan_->plan->route().route));
    doc_.setValue(routePath(&sim::RouteConfig::source), sourceName(sim::RouteSource::kBlocks));
    doc_.endMacro();
    form_->reveal(QString::fromStdString(routePath(&sim::RouteConfig::blocks)));
  });
  asBlocks->setToolTip(
      "Turn the current main track into route.blocks, one editable entry per block");

  QMenu* run = menuBar()->addMenu("R&un");
  QAction* generate = run->addAction("&Generate dataset", this, [this] {
    const QString out = out_dir_->text();
    const bool has_dataset = QFileInfo::exists(out + "/" + io::DatasetLayout::kManifest) ||
                             QFileInfo::exists(out + "/" + io::DatasetLayout::kStateDir);
    if (has_dataset &&
        QMessageBox::question(this, "Generate dataset",
                              out + " already holds a dataset. Start over and replace it?") !=
            QMessageBox::Yes)
      return;
    startRun(out, has_dataset);
  });
  generate->setShortcut(Qt::Key_F5);
  run->addAction(exportAction);

  QToolBar* bar = addToolBar("Main");
  bar->setObjectName("mainToolBar");
  bar->addAction(undo);
  bar->addAction(redo);
  bar->addSeparator();
  bar->addAction(regenerate);
  bar->addAction(asBlocks);
  bar->addSeparator();
  bar->addWidget(new QLabel(" Output folder "));
  out_dir_ = new QLineEdit(QDir::current().absoluteFilePath("output"));
  out_dir_->setObjectName("outputFolder");
  out_dir_->setMinimumWidth(260);
  bar->addWidget(out_dir_);
  bar->addAction(generate);
  bar->addAction(exportAction);
}

void MainWindow::updateTitle() {
  const QString name = doc_.filePath().isEmpty() ? "untitled scenario" : doc_.filePath();
  setWindowTitle(QString("TrainSim Studio — %1%2").arg(name, doc_.isModified() ? " *" : ""));
}

void MainWindow::onDocumentChanged() {
  const std::optional<scenario::Scenario>& sc = doc_.resolved();
  showReport();
  if (!sc) {
    status_->setText(QString("%1 invalid value(s): the plan shows the last valid scenario")
                         .arg(doc_.problems().size()));
    return;
  }
  plan_error_.clear();
  planner_.request(*sc);
}

void MainWindow::onPlanned(std::shared_ptr<const PlanSnapshot> plan) {
  plan_ = std::move(plan);
  plan_error_.clear();
  view3d_->setPlan(plan_);
  view2d_->setPlan(plan_);
  inertial_->setPlan(plan_);
  scene_->setPlan(plan_);
  showReport();
  const auto& main = plan_->plan->route().route;
  status_->setText(QString("plan: %1 km, %2 blocks, %3 tracks, %4 violation(s), run %5 s")
                       .arg(main.track.length() / 1000.0, 0, 'f', 2)
                       .arg(main.blocks.size())
                       .arg(plan_->tracks.size())
                       .arg(plan_->violations.size())
                       .arg(plan_->duration_s, 0, 'f', 1));
  emit planShown();
}

void MainWindow::showReport() {
  report_->setRowCount(0);
  auto add = [this](const QStringList& cells) {
    const int r = report_->rowCount();
    report_->insertRow(r);
    for (int c = 0; c < cells.size(); ++c)
      report_->setItem(r, c, new QTableWidgetItem(cells[c]));
  };
  for (const scenario::Problem& p : doc_.problems())
    add({"invalid value", "", "", "", "", QString::fromStdString(p.text())});
  if (!plan_error_.isEmpty())
    add({"plan failed", "", "", "", "", plan_error_});
  if (plan_) {
    for (const track::Violation& v : plan_->plan->violations())
      add({QString::fromStdString(v.rule),
           QString("%1 – %2").arg(v.chainage_begin_m, 0, 'f', 1).arg(v.chainage_end_m, 0, 'f', 1),
           QString::number(v.block_id), QString::number(v.value, 'g', 5),
           QString::number(v.limit, 'g', 5) + " " + QString::fromStdString(v.unit),
           QString::fromStdString(v.message)});
  }
  report_->resizeColumnsToContents();
}

void MainWindow::showMessage(const QString& title, const QString& text, const QString& details) {
  auto* box = new QMessageBox(QMessageBox::Warning, title, text, QMessageBox::Ok, this);
  box->setObjectName("problemsDialog");
  box->setInformativeText(details);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();  // window-modal, not blocking: the studio stays usable behind it
}

bool MainWindow::openScenario(const QString& path) {
  try {
    doc_.open(path);
  } catch (const std::exception& e) {
    showMessage("Cannot open scenario", QString("%1 was not opened.").arg(path),
                QString::fromUtf8(e.what()));
    return false;
  }
  if (!doc_.problems().empty()) {
    QStringList lines;
    for (const scenario::Problem& p : doc_.problems())
      lines << QString::fromStdString(p.text());
    showMessage("Invalid scenario",
                QString("%1 has %2 invalid value(s). They are marked at their fields; the plan "
                        "updates once they are fixed.")
                    .arg(path)
                    .arg(lines.size()),
                lines.join("\n"));
  }
  return true;
}

bool MainWindow::save() {
  if (doc_.filePath().isEmpty())
    return saveAs();
  try {
    doc_.save(doc_.filePath());
    return true;
  } catch (const std::exception& e) {
    showMessage("Cannot save", "The scenario was not saved.", QString::fromUtf8(e.what()));
    return false;
  }
}

bool MainWindow::saveAs() {
  const QString f =
      QFileDialog::getSaveFileName(this, "Save scenario", doc_.baseDir(), "Scenario (*.json)");
  if (f.isEmpty())
    return false;
  try {
    doc_.save(f);
    return true;
  } catch (const std::exception& e) {
    showMessage("Cannot save", "The scenario was not saved.", QString::fromUtf8(e.what()));
    return false;
  }
}

bool MainWindow::startRun(const QString& out, bool force) {
  const std::optional<scenario::Scenario>& sc = doc_.resolved();
  if (!sc) {
    showMessage("Cannot generate", "Fix the marked values first.",
                QString::fromStdString(doc_.problems().front().text()));
    return false;
  }
  if (!runner_.start(*sc, out, force))
    return false;
  cancel_->setEnabled(true);
  progress_->setValue(0);
  progress_->setFormat("starting…");
  status_->setText("generating " + out);
  return true;
}

void MainWindow::onRunFinished(int code, const QString& message, const QString& out) {
  cancel_->setEnabled(false);
  if (code == 0) {
    progress_->setValue(1000);
    progress_->setFormat("done");
    status_->setText(message);
    openDataset(out);
    return;
  }
  progress_->setFormat(code == 130 ? "cancelled" : "failed");
  status_->setText(message);
  if (code != 130)
    showMessage("Generation failed",
                QString("The run into %1 stopped (exit code %2).").arg(out).arg(code), message);
}

bool MainWindow::openDataset(const QString& root) {
  try {
    inertial_->setDataset(root);
    scans_->setDataset(root);  // says in its own status line when there is nothing to show
    return true;
  } catch (const std::exception& e) {
    showMessage("Cannot open dataset", root + " could not be read.", QString::fromUtf8(e.what()));
    return false;
  }
}

void MainWindow::selectTime(double t_s) {
  if (!plan_)
    return;
  const TrainPose pose = plan_->poseAt(t_s);
  view3d_->markTrain(pose);
  view2d_->markTrain(pose);
  status_->setText(
      QString("t = %1 s, chainage %2 m").arg(pose.t_s, 0, 'f', 2).arg(pose.chainage_m, 0, 'f', 1));
}

bool MainWindow::maybeSave() {
  if (!doc_.isModified())
    return true;
  const auto answer =
      QMessageBox::question(this, "Unsaved changes", "Save the scenario first?",
                            QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel);
  return answer == QMessageBox::Discard || (answer == QMessageBox::Save && save());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (!maybeSave()) {
    event->ignore();
    return;
  }
  if (runner_.running())
    runner_.cancel();
  event->accept();
}

}  // namespace trainsim::studio
