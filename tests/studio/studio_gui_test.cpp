// The studio's GUI suite: drives the real main window as a user would (fields, menus, mouse)
// and checks what it shows against the modules and the files the run wrote. Runs under Xvfb
// (tests/studio/with-xvfb.sh). With TRAINSIM_SCREENSHOT_DIR set it also saves the screenshots
// in docs/ (scripts/studio-screenshots.sh).

#include "studio_gui_test.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <QAction>
#include <QApplication>
#include <QFile>
#include <QFileInfo>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QSignalSpy>
#include <QSurfaceFormat>
#include <QTableWidget>
#include <QtTest>

#include "design_view_3d.hpp"
#include "inertial_panel.hpp"
#include "plan_view_2d.hpp"
#include "schema_form.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

using trainsim::studio::MainWindow;

namespace {

// Menu action by its text (without the & accelerators).
QAction* findAction(QWidget* window, const QString& text) {
  for (QAction* a : window->findChildren<QAction*>()) {
    if (a->text().remove('&') == text)
      return a;
  }
  return nullptr;
}

// The visible problems dialog, if any.
QMessageBox* problemsDialog() {
  QApplication::processEvents();
  for (QWidget* w : QApplication::topLevelWidgets()) {
    if (auto* box = qobject_cast<QMessageBox*>(w); box && box->isVisible())
      return box;
  }
  return nullptr;
}

}  // namespace

// Types `text` into a generated field and commits it as a user does (Return).
void typeInto(trainsim::studio::MainWindow& w, const QString& path, const QString& text) {
  w.form()->reveal(path);
  auto* edit = qobject_cast<QLineEdit*>(w.form()->editor(path));
  QVERIFY2(edit != nullptr, qPrintable("no line edit for " + path));
  edit->selectAll();
  QTest::keyClicks(edit, text);
  QTest::keyClick(edit, Qt::Key_Return);
}

void StudioGuiTest::initTestCase() {
  QVERIFY(tmp_.isValid());
  window_ = std::make_unique<MainWindow>();
  window_->show();
  QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
}

void StudioGuiTest::opensTheDefaultScenarioAndPlansIt() {
  MainWindow& w = *window_;
  QSignalSpy shown(&w, &MainWindow::planShown);
  if (!w.plan())
    QVERIFY(shown.wait(60000));
  QVERIFY(w.document()->problems().empty());
  QCOMPARE(w.document()->json()["seed"].get<int>(), 5);  // configs/default.json
  const auto plan = w.plan();
  QVERIFY(plan);
  // Every track of the layout is drawn, segment by segment, in the 3D view.
  int segments = 0;
  for (const auto& t : plan->tracks)
    segments += static_cast<int>(t.segment_type.size());
  QVERIFY(plan->tracks.size() >= 2);  // the default has double track
  QCOMPARE(w.view3d()->segmentCount(), segments);
  QCOMPARE(w.view3d()->labelCount(), static_cast<int>(plan->chainage_marks.size()));
  QCOMPARE(w.view2d()->violationCount(), static_cast<int>(plan->violations.size()));
  // The schema's fields are all there, with their descriptions as tooltips.
  QWidget* length = w.form()->editor("route.generator.length_m");
  QVERIFY(length);
  QVERIFY(length->toolTip().contains("Route length"));
  QVERIFY(length->toolTip().contains("Range: 500"));
  QVERIFY(w.form()->editor("sensors.imus[0].rate_hz") ||
          w.form()->editor("sensors.imus[0].period_ns"));
}

void StudioGuiTest::editingACurveRadiusUpdatesThePlan() {
  MainWindow& w = *window_;
  QSignalSpy shown(&w, &MainWindow::planShown);
  // The generated route becomes an editable block list (same geometry).
  const double length_before = w.plan()->plan->route().route.track.length();
  const Eigen::Vector2d end_before = [&] {
    const auto& t = w.plan()->plan->route().route.track;
    return t.horizontal().at(t.length()).position_m;
  }();
  findAction(&w, "Edit as block list")->trigger();
  QVERIFY(shown.wait(60000));
  QCOMPARE(w.document()->json()["route"]["source"].get<std::string>(), std::string("blocks"));
  QVERIFY(std::abs(w.plan()->plan->route().route.track.length() - length_before) < 1e-6);
  // First curve in the list, and the route block it becomes.
  const auto& blocks = w.document()->json()["route"]["blocks"];
  int curve = -1;
  for (std::size_t i = 0; i < blocks.size() && curve < 0; ++i) {
    if (blocks[i]["type"] == "curve")
      curve = static_cast<int>(i);
  }
  QVERIFY(curve >= 0);
  const auto& route_blocks = w.plan()->plan->route().route.blocks;
  const double old_radius = std::abs(route_blocks[static_cast<std::size_t>(curve)].radius_m);
  const double new_radius = std::round(old_radius * 1.5);
  const QString field = QString("route.blocks[%1].radius_m").arg(curve);
  shown.clear();
  typeInto(w, field, QString::number(new_radius));
  QVERIFY(shown.wait(60000));
  const auto& after = w.plan()->plan->route().route.blocks;
  QCOMPARE(std::abs(after[static_cast<std::size_t>(curve)].radius_m), new_radius);
  // Same chainage length (arc and transitions are unchanged), different end of line.
  const auto end_of = [&] {
    const auto& t = w.plan()->plan->route().route.track;
    return t.horizontal().at(t.length()).position_m;
  };
  QVERIFY((end_of() - end_before).norm() > 1.0);
  QCOMPARE(w.document()->undoStack()->undoText(), QString("Set ") + field);
  // Undo brings the old radius (and plan) back; redo the new one.
  shown.clear();
  w.document()->undoStack()->undo();
  QVERIFY(shown.wait(60000));
  QCOMPARE(std::abs(w.plan()->plan->route().route.blocks[static_cast<std::size_t>(curve)].radius_m),
           old_radius);
  QCOMPARE(qobject_cast<QLineEdit*>(w.form()->editor(field))->text().toDouble(), old_radius);
  shown.clear();
  w.document()->undoStack()->redo();
  QVERIFY(shown.wait(60000));
  QCOMPARE(std::abs(w.plan()->plan->route().route.blocks[static_cast<std::size_t>(curve)].radius_m),
           new_radius);

  // A radius far below the design minimum: the report's violations appear in both views
  // and in the report table, on that curve.
  shown.clear();
  typeInto(w, field, "300");
  QVERIFY(shown.wait(60000));
  const auto& violations = w.plan()->plan->violations();
  QVERIFY(!violations.empty());
  QCOMPARE(w.view3d()->violationCount(), static_cast<int>(violations.size()));
  QCOMPARE(w.view2d()->violationCount(), static_cast<int>(violations.size()));
  bool min_radius = false;
  for (int r = 0; r < w.report()->rowCount(); ++r)
    min_radius = min_radius || (w.report()->item(r, 0)->text() == "min_radius" &&
                                w.report()->item(r, 2)->text() == QString::number(curve));
  QVERIFY(min_radius);
  shown.clear();
  w.document()->undoStack()->undo();
  QVERIFY(shown.wait(60000));
  QVERIFY(w.plan()->plan->violations().size() < violations.size() || violations.empty());
}

void StudioGuiTest::anOutOfRangeValueIsMarkedAtItsField() {
  MainWindow& w = *window_;
  const auto plan_before = w.plan();
  typeInto(w, "layout.track_centre_distance_m", "1.5");
  QVERIFY(!w.document()->problems().empty());
  const QString error = w.form()->errorAt("layout.track_centre_distance_m");
  QVERIFY2(error.contains("below the minimum 3"), qPrintable(error));
  auto* label = w.findChild<QLabel*>("layout.track_centre_distance_m/error");
  QVERIFY(label && label->isVisible());
  QCOMPARE(label->text(), error);
  QVERIFY(w.report()->rowCount() > 0);
  QVERIFY(w.report()->item(0, 5)->text().startsWith("layout.track_centre_distance_m"));
  QTest::qWait(400);
  QCOMPARE(w.plan(), plan_before);  // no plan of an invalid scenario
  // Text that is not a number is the validator's to reject, too.
  typeInto(w, "layout.track_centre_distance_m", "four");
  QVERIFY(!w.form()->errorAt("layout.track_centre_distance_m").isEmpty());
  QSignalSpy shown(&w, &MainWindow::planShown);
  typeInto(w, "layout.track_centre_distance_m", "4.5");
  QVERIFY(w.form()->errorAt("layout.track_centre_distance_m").isEmpty());
  QVERIFY(!label->isVisible());
  QVERIFY(shown.wait(60000));
  QCOMPARE(w.plan()->plan->layout().tracks[1].offset_m, -4.5);
}

void StudioGuiTest::aTrainOrSensorEditDoesNotRebuildTheRouteOrLayout() {
  MainWindow& w = *window_;
  const trainsim::sim::Planner& planner = w.planService().planner();
  const auto route = planner.builds("route"), layout = planner.builds("layout"),
             motion = planner.builds("motion");
  QVERIFY(route > 0 && layout > 0 && motion > 0);
  QSignalSpy shown(&w, &MainWindow::planShown);
  typeInto(w, "train.max_accel_m_s2", "0.7");
  QVERIFY(shown.wait(60000));
  QCOMPARE(planner.builds("route"), route);
  QCOMPARE(planner.builds("layout"), layout);
  QCOMPARE(planner.builds("motion"), motion + 1);
  typeInto(w, "sensors.imus[0].period_ns", "20000000");
  QTest::qWait(600);
  QCOMPARE(planner.builds("route"), route);
  QCOMPARE(planner.builds("layout"), layout);
  QCOMPARE(planner.builds("motion"), motion + 1);
  typeInto(w, "train.max_accel_m_s2", "0.8");
  QVERIFY(shown.wait(60000));
}

void StudioGuiTest::selectingATimeMarksTheTrain() {
  MainWindow& w = *window_;
  trainsim::studio::InertialPanel* panel = w.inertial();
  panel->showView("Trajectory over time");
  w.resize(1500, 920);
  QTest::qWait(100);
  const double t = 0.4 * w.plan()->duration_s;
  QSignalSpy selected(panel->plots(), &trainsim::studio::PlotPanel::xSelected);
  QTest::mouseClick(panel->plots()->plotWidget(), Qt::LeftButton, {},
                    panel->plots()->pixelOf(0, t));
  QCOMPARE(selected.size(), 1);
  const double clicked = selected.front().at(0).toDouble();
  QVERIFY(std::abs(clicked - t) < 0.01 * w.plan()->duration_s);  // within a few pixels
  QVERIFY(w.view3d()->trainVisible());
  // The marker is where the planned trajectory puts the train at the clicked time.
  const auto pose = w.plan()->poseAt(clicked);
  QVERIFY((w.view3d()->trainPosition() - pose.position).norm() < 1e-6);
  QVERIFY(w.findChild<QLabel*>("statusText")->text().contains("chainage"));
}

void StudioGuiTest::cancelStopsARunWithoutAFinishedDataset() {
  MainWindow& w = *window_;
  // A long route, so the run is still going when cancelled.
  w.document()->setValue("route.source", "generated");
  w.document()->setValue("route.generator.length_m", 200000.0);
  const QString out = tmp_.filePath("cancelled");
  QSignalSpy done(w.runner(), &trainsim::studio::RunController::finished);
  QSignalSpy progress(w.runner(), &trainsim::studio::RunController::progress);
  QVERIFY(w.startRun(out, false));
  QVERIFY(progress.wait(120000));
  QTest::mouseClick(w.findChild<QPushButton*>("cancelRun"), Qt::LeftButton);
  QVERIFY(done.wait(120000));
  QCOMPARE(done.front().at(0).toInt(), 130);
  QVERIFY(!QFileInfo::exists(out + "/manifest.json"));
  QCOMPARE(w.progressBar()->format(), QString("cancelled"));
  w.document()->undoStack()->undo();
  w.document()->undoStack()->undo();
}

void StudioGuiTest::aBrokenScenarioShowsTheValidatorsMessagesAndTheStudioStaysUsable() {
  MainWindow& w = *window_;
  const QString broken = tmp_.filePath("broken.json");
  {
    QFile f(broken);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write(R"({"route": {"generator": {"length_m": -5}}, "design": {"design_speed_kmh": 100}})");
  }
  QVERIFY(w.openScenario(broken));
  QVERIFY(!w.document()->problems().empty());
  QMessageBox* box = problemsDialog();
  QVERIFY(box);
  QVERIFY2(box->informativeText().contains("route.generator.length_m"),
           qPrintable(box->informativeText()));
  QVERIFY(box->informativeText().contains("design.design_speed_kmh"));  // unknown key
  QVERIFY(!w.form()->errorAt("route.generator.length_m").isEmpty());
  box->close();
  QTest::qWait(50);
  // Still usable: fix the fields and the plan follows.
  QSignalSpy shown(&w, &MainWindow::planShown);
  typeInto(w, "route.generator.length_m", "3000");
  w.document()->setValue("design", trainsim::sim::loadScenario("").json()["design"]);
  QVERIFY(w.document()->problems().empty());
  QVERIFY(shown.wait(60000));
  QVERIFY(std::abs(w.plan()->plan->route().route.track.length() - 3000.0) < 1e-6);

  // Not JSON at all: nothing is loaded, the current scenario stays.
  const QString garbage = tmp_.filePath("garbage.json");
  {
    QFile f(garbage);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write("{ \"seed\": ");
  }
  const auto before = w.document()->json();
  QVERIFY(!w.openScenario(garbage));
  box = problemsDialog();
  QVERIFY(box);
  QVERIFY2(box->informativeText().contains("malformed JSON"), qPrintable(box->informativeText()));
  box->close();
  QCOMPARE(w.document()->json(), before);
}

void StudioGuiTest::cleanupTestCase() {
  window_->document()->undoStack()->setClean();  // no "save changes?" on close
  window_.reset();
}

int main(int argc, char** argv) {
  // As trainsim-studio does: VTK's OpenGL format before the application.
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  StudioGuiTest test;
  return QTest::qExec(&test, argc, argv);
}
