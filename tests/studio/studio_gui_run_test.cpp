// The studio's GUI suite, continued: the run's outputs in the scan view (scans, pictures,
// labels, clicks), the Scene tab, and the screenshots for docs/ (see studio_gui_test.hpp).

#include "studio_gui_test.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QRegularExpression>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTabWidget>
#include <QtTest>
#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "inertial_panel.hpp"
#include "scan_view.hpp"
#include "scene_view.hpp"
#include "schema_form.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/scene/semantics.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/terrain/railway.hpp"

using trainsim::studio::MainWindow;

namespace {

struct ImuRow {
  double t_s, ax;
};

// imu.csv read independently of the studio's reader.
std::vector<ImuRow> readImuCsv(const QString& path) {
  std::ifstream in(path.toStdString());
  std::string line;
  std::getline(in, line);
  std::vector<ImuRow> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string t, ax;
    std::getline(ss, t, ',');
    std::getline(ss, ax, ',');
    rows.push_back({std::stod(t) * 1e-9, std::stod(ax)});
  }
  return rows;
}

}  // namespace

void StudioGuiTest::aRunGoesToTheEndAndTheImuPlotHoldsItsSamples() {
  MainWindow& w = *window_;
  const QString out = tmp_.filePath("run");
  QSignalSpy done(w.runner(), &trainsim::studio::RunController::finished);
  QSignalSpy progress(w.runner(), &trainsim::studio::RunController::progress);
  QVERIFY(w.startRun(out, false));
  QVERIFY(done.wait(300000));
  QCOMPARE(done.front().at(0).toInt(), 0);
  QVERIFY(!progress.isEmpty());
  QCOMPARE(w.progressBar()->value(), 1000);
  QVERIFY(QFileInfo::exists(out + "/manifest.json"));
  const QString imu_csv = out + "/sequences/00/imu.csv";
  QVERIFY(QFileInfo::exists(imu_csv));

  trainsim::studio::InertialPanel* panel = w.inertial();
  const QString view = "IMU imu: accelerometer vs truth";
  QVERIFY2(panel->views().contains(view), qPrintable(panel->views().join(", ")));
  panel->showView(view);
  QCOMPARE(panel->plots()->rowCount(), 3);
  const std::vector<ImuRow> rows = readImuCsv(imu_csv);
  const auto plotted = panel->plots()->data(0, 0);
  QCOMPARE(plotted.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    QCOMPARE(plotted[i].first, rows[i].t_s);
    QCOMPARE(plotted[i].second, rows[i].ax);
  }
  QVERIFY(panel->plots()->seriesName(0, 1).startsWith("truth"));
  // Every sensor of the run has its view against truth.
  for (const char* v : {"GNSS gnss: error vs truth", "Odometer odometer vs truth",
                        "Balises balises vs truth", "IMU imu: gyroscope vs truth"}) {
    QVERIFY2(panel->views().contains(v), qPrintable(v));
    panel->showView(v);
    QVERIFY(panel->plots()->rowCount() >= 2);
    QVERIFY(!panel->plots()->data(0, 0).empty());
  }
}

// The run above opened its dataset in the scan view: its scans and pictures are shown with
// their labels, read back here by the test's own readers (KITTI's .bin, SemanticKITTI's
// .label, Qt's PNG reader), driven through the view's own controls; a scan whose files
// disagree is reported, not drawn.
void StudioGuiTest::theRunsScansAndPicturesAreShownWithTheirLabels() {
  using trainsim::studio::ScanView;
  MainWindow& w = *window_;
  ScanView* view = w.scans();
  const QString seq = tmp_.filePath("run") + "/sequences/00";
  QVERIFY(QFileInfo::exists(seq + "/velodyne/000000.bin"));
  QCOMPARE(view->lidars(), QStringList{"velodyne"});
  QCOMPARE(view->cameras(), QStringList{"image_2"});
  QCOMPARE(view->frameCount(),
           static_cast<int>(QDir(seq + "/velodyne").entryList(QDir::Files).size()));
  auto* frame = view->findChild<QSpinBox*>("scanFrame");
  QVERIFY(frame);
  frame->setValue(42);
  QCOMPARE(view->frame(), 42);
  const auto bytes = [](const QString& path) {
    QFile f(path);
    return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
  };
  const QByteArray bin = bytes(seq + "/velodyne/000042.bin");
  const QByteArray label = bytes(seq + "/labels/000042.label");
  QVERIFY(bin.size() > 16 * 10000);
  QCOMPARE(view->pointCount(), bin.size() / 16);
  QCOMPARE(label.size() / 4, bin.size() / 16);
  std::vector<std::uint32_t> words(static_cast<std::size_t>(label.size() / 4));
  std::memcpy(words.data(), label.constData(), static_cast<std::size_t>(label.size()));
  std::vector<float> xyzi(static_cast<std::size_t>(bin.size() / 4));
  std::memcpy(xyzi.data(), bin.constData(), static_cast<std::size_t>(bin.size()));
  std::map<int, int> counts;
  for (const std::uint32_t word : words)
    ++counts[static_cast<int>(word & 0xFFFFu)];
  QCOMPARE(view->classCounts(), counts);
  QVERIFY(counts.size() >= 5);  // rails, sleepers, trackbed, terrain, poles at least
  // Every point in its class's colour (grey for unlabelled, which the table has black).
  auto* colour = view->findChild<QComboBox*>("scanColour");
  QVERIFY(colour);
  colour->setCurrentIndex(0);
  for (std::size_t i = 0; i < words.size(); ++i) {
    const auto want = ScanView::classColour(words[i] & 0xFFFFu);
    if (view->pointColour(static_cast<int>(i)) != want)
      QFAIL(qPrintable(QString("point %1 not in its class's colour").arg(i)));
    if ((words[i] & 0xFFFFu) != 0 && want != trainsim::scene::classes()[words[i] & 0xFFFFu].colour)
      QFAIL("a labelled class drawn in another colour than the class table's");
  }
  // Every point in its intensity's colour on the ramp.
  colour->setCurrentIndex(2);
  for (std::size_t i = 0; i < words.size(); ++i)
    if (view->pointColour(static_cast<int>(i)) != ScanView::ramp(xyzi[4 * i + 3]))
      QFAIL(qPrintable(QString("point %1 not in its intensity's colour").arg(i)));

  const QImage rgb(seq + "/image_2/000042.png");
  QCOMPARE(view->picture().size(), rgb.size());
  for (int k = 0; k < 50; ++k) {
    const QPoint p((k * 131) % rgb.width(), (k * 71) % rgb.height());
    QCOMPARE(view->picture().pixel(p), rgb.pixel(p));
  }
  auto* picture = view->findChild<QComboBox*>("scanPicture");
  QVERIFY(picture);
  picture->setCurrentIndex(1);  // semantic
  const QImage ids(seq + "/semantic_2/000042.png");
  QCOMPARE(view->picture().size(), ids.size());
  for (int k = 0; k < 50; ++k) {
    const QPoint p((k * 131) % ids.width(), (k * 71) % ids.height());
    const auto c = ScanView::classColour(static_cast<std::uint32_t>(qGray(ids.pixel(p))));
    QCOMPARE(view->picture().pixel(p), qRgb(c[0], c[1], c[2]));
  }
  picture->setCurrentIndex(2);  // depth: metres × 256, near bright
  const QImage depth(seq + "/depth_2/000042.png");
  QCOMPARE(depth.format(), QImage::Format_Grayscale16);
  int measured = 0;
  for (int v = 0; v < depth.height(); v += 7)
    for (int u = 0; u < depth.width(); u += 13) {
      const quint16 d = reinterpret_cast<const quint16*>(depth.constScanLine(v))[u];
      const auto c = d == 0 ? std::array<std::uint8_t, 3>{0, 0, 0}
                            : ScanView::ramp(1.0 - std::min(d / 256.0, 80.0) / 80.0);
      measured += d != 0;
      QCOMPARE(view->picture().pixel(u, v), qRgb(c[0], c[1], c[2]));
    }
  QVERIFY(measured > 100);
  QVERIFY(view->status().contains("frame 42"));

  // A .label cut short: the scan is not drawn, and the status line names the file; with the
  // .label gone, the points are drawn unlabelled and the status line says so.
  QFile cut(seq + "/labels/000001.label");
  QVERIFY(cut.resize(cut.size() - 4));
  frame->setValue(1);
  QCOMPARE(view->pointCount(), 0);
  QVERIFY2(view->status().contains("000001.label"), qPrintable(view->status()));
  QVERIFY(QFile::remove(seq + "/labels/000002.label"));
  frame->setValue(2);
  QVERIFY(view->pointCount() > 10000);
  QCOMPARE(view->classCounts(), (std::map<int, int>{}));
  QVERIFY2(view->status().contains("000002.label is missing"), qPrintable(view->status()));
  picture->setCurrentIndex(0);
  colour->setCurrentIndex(0);
}

// The scan's points drawn on the picture where calib.txt projects them land where the camera
// saw the same surfaces: on the camera's own depth and class there (the LiDAR's Embree hits
// against the camera's VTK render, through the calibration the run wrote, read by the test
// with Qt's PNG reader), and the pixels drawn are the points' colours.
void StudioGuiTest::lidarPointsOnThePictureLandWhereTheCameraSawThem() {
  using trainsim::studio::ScanView;
  ScanView* view = window_->scans();
  const QString seq = tmp_.filePath("run") + "/sequences/00";
  view->findChild<QSpinBox*>("scanFrame")->setValue(42);
  view->findChild<QComboBox*>("scanColour")->setCurrentIndex(0);   // class
  view->findChild<QComboBox*>("scanPicture")->setCurrentIndex(0);  // RGB
  auto* overlay = view->findChild<QCheckBox*>("scanOverlay");
  QVERIFY(overlay && !overlay->isChecked());
  const QImage plain = view->picture();
  QVERIFY(!view->projected().empty());  // the projection does not wait for the tick
  overlay->setChecked(true);
  const std::vector<ScanView::Projected> points = view->projected();
  QVERIFY2(points.size() > 3000, qPrintable(QString::number(points.size())));

  QFile label_file(seq + "/labels/000042.label");
  QVERIFY(label_file.open(QIODevice::ReadOnly));
  const QByteArray label = label_file.readAll();
  const QImage depth(seq + "/depth_2/000042.png"), ids(seq + "/semantic_2/000042.png");
  QCOMPARE(depth.format(), QImage::Format_Grayscale16);
  // A point lands on its surface when its depth lies within the depths of the 3 × 3 pixels
  // around where it lands (its position within its pixel is not known, and the ground at a
  // grazing angle changes depth fast across one), widened by three times the range noise's
  // sigma (0.02 m). The camera's far terrain is simplified (its level of detail), which the
  // LiDAR's is not: a few per cent of the ground's points miss for that.
  const auto depth_at = [&](int u, int v) {
    return reinterpret_cast<const quint16*>(depth.constScanLine(v))[u] / 256.0;
  };
  std::vector<double> signed_errors;
  int on_surface = 0, same_class = 0;
  for (const ScanView::Projected& p : points) {
    const int u = static_cast<int>(std::lround(p.u)), v = static_cast<int>(std::lround(p.v));
    QVERIFY(u >= 0 && u < depth.width() && v >= 0 && v < depth.height());
    std::uint32_t word = 0;
    std::memcpy(&word, label.constData() + 4 * p.point, 4);
    same_class += qGray(ids.pixel(u, v)) == static_cast<int>(word & 0xFFFFu);
    if (depth_at(u, v) == 0.0)
      continue;
    signed_errors.push_back(p.depth - depth_at(u, v));
    double lo = 1e9, hi = 0.0;
    for (int j = std::max(0, v - 1); j <= std::min(depth.height() - 1, v + 1); ++j)
      for (int i = std::max(0, u - 1); i <= std::min(depth.width() - 1, u + 1); ++i)
        if (const double d = depth_at(i, j); d > 0.0) {
          lo = std::min(lo, d);
          hi = std::max(hi, d);
        }
    on_surface += p.depth >= lo - 0.06 && p.depth <= hi + 0.06;
  }
  const std::size_t measured = signed_errors.size();
  QVERIFY(measured > points.size() * 9 / 10);
  std::sort(signed_errors.begin(), signed_errors.end());
  const double bias = signed_errors[measured / 2];
  const double share = static_cast<double>(on_surface) / static_cast<double>(measured);
  const double class_share = static_cast<double>(same_class) / static_cast<double>(points.size());
  qInfo(
      "%zu points on the picture: %.1f %% on the camera's surface there, depth bias "
      "(median) %.4f m, %.1f %% on their own class",
      points.size(), 100.0 * share, bias, 100.0 * class_share);
  QVERIFY2(share > 0.93 && std::abs(bias) < 0.02 && class_share > 0.9,
           "points off the camera's view");

  // Drawn: the pixels changed are the points' class colours, and unticking restores the
  // picture.
  std::set<QRgb> colours;
  for (const ScanView::Projected& p : points) {
    const auto c = view->pointColour(p.point);
    colours.insert(qRgb(c[0], c[1], c[2]));
  }
  const QImage drawn = view->picture();
  QCOMPARE(drawn.size(), plain.size());
  int changed = 0;
  for (int v = 0; v < drawn.height(); ++v)
    for (int u = 0; u < drawn.width(); ++u)
      if (drawn.pixel(u, v) != plain.pixel(u, v)) {
        ++changed;
        if (!colours.count(drawn.pixel(u, v)))
          QFAIL("a pixel drawn in a colour that is no point's");
      }
  QVERIFY(changed > static_cast<int>(points.size()));
  overlay->setChecked(false);
  QCOMPARE(view->picture(), plain);
}

// A click on the picture says what the camera saw there: the class, the instance with its
// track and state from instances.csv (a signal's aspect), the depth; read here from the PNGs
// and instances.csv on their own.
void StudioGuiTest::aClickOnThePictureSaysWhatIsThere() {
  using trainsim::studio::ScanView;
  ScanView* view = window_->scans();
  const QString seq = tmp_.filePath("run") + "/sequences/00";
  view->findChild<QComboBox*>("scanPicture")->setCurrentIndex(0);  // RGB
  QFile csv(seq + "/instances.csv");
  QVERIFY(csv.open(QIODevice::ReadOnly | QIODevice::Text));
  QCOMPARE(QString::fromUtf8(csv.readLine()).trimmed(),
           QString("instance,scene_instance,class,track,state"));
  std::map<int, QStringList> rows;
  while (!csv.atEnd()) {
    const QStringList cells = QString::fromUtf8(csv.readLine()).trimmed().split(',');
    rows[cells[0].toInt()] = cells;
  }
  // The first frame with a signal within the depth images' reach, at a pixel inside it (its
  // 5 × 5 pixels the same signal: a click on the picture, scaled down to its pane, cannot
  // hit one pixel exactly); failing that, a rail (a track, no state).
  int frame = -1, u = 0, v = 0;
  for (const bool signal : {true, false}) {
    for (int f = 0; f < view->frameCount() && frame < 0; ++f) {
      const QString name = QString("/%1.png").arg(f, 6, 10, QChar('0'));
      const QImage ids(seq + "/instance_2" + name), depths(seq + "/depth_2" + name);
      const auto id = [&](int i, int j) {
        return static_cast<int>(reinterpret_cast<const quint16*>(ids.constScanLine(j))[i]);
      };
      for (int j = 1; j + 1 < ids.height() && frame < 0; ++j)
        for (int i = 1; i + 1 < ids.width() && frame < 0; ++i) {
          const auto row = rows.find(id(i, j));
          if (row == rows.end() || row->second.size() < 5 || row->second[3].isEmpty() ||
              row->second[4].isEmpty() == signal ||
              reinterpret_cast<const quint16*>(depths.constScanLine(j))[i] == 0)
            continue;
          bool inside = j >= 2 && i >= 2 && j + 2 < ids.height() && i + 2 < ids.width();
          for (int dj = -2; dj <= 2 && inside; ++dj)
            for (int di = -2; di <= 2; ++di)
              inside = inside && id(i + di, j + dj) == id(i, j);
          if (inside) {
            frame = f;
            u = i;
            v = j;
          }
        }
    }
    if (frame >= 0)
      break;
  }
  QVERIFY2(frame >= 0, "no signal or rail in any picture of the run");
  view->findChild<QSpinBox*>("scanFrame")->setValue(frame);
  const QString name = QString("/%1.png").arg(frame, 6, 10, QChar('0'));
  const QImage cls(seq + "/semantic_2" + name), ids(seq + "/instance_2" + name),
      depth(seq + "/depth_2" + name);
  const int id = reinterpret_cast<const quint16*>(ids.constScanLine(v))[u];
  const quint16 d = reinterpret_cast<const quint16*>(depth.constScanLine(v))[u];
  const QStringList& row = rows.at(id);
  QString about = "track " + row[3];
  if (!row[4].isEmpty())
    about += ", " + row[4];
  const QString expected =
      QString("pixel (%1, %2): %3, instance %4 (%5), %6 m")
          .arg(u)
          .arg(v)
          .arg(QString::fromStdString(trainsim::scene::classes()[qGray(cls.pixel(u, v))].name))
          .arg(id)
          .arg(about)
          .arg(d / 256.0, 0, 'f', 2);
  QCOMPARE(view->describePixel(u, v), expected);
  qInfo("frame %d: %s", frame, qPrintable(expected));
  QVERIFY(view->describePixel(-1, v).isEmpty());
  QVERIFY(view->describePixel(u, view->picture().height()).isEmpty());

  // A click at that pixel's centre on the scaled picture puts it in the status line.
  auto* label = view->findChild<QLabel*>("scanImage");
  const QImage picture = view->picture();
  const QSize shown = picture.size().scaled(label->size(), Qt::KeepAspectRatio);
  const double scale = static_cast<double>(shown.width()) / picture.width();
  const QPoint at(
      static_cast<int>(std::lround((label->width() - shown.width()) / 2.0 + (u + 0.5) * scale)),
      static_cast<int>(std::lround((label->height() - shown.height()) / 2.0 + (v + 0.5) * scale)));
  QTest::mouseClick(label, Qt::LeftButton, Qt::NoModifier, at);
  // The pixel under the click, to within the pane's resolution (a pane pixel covers
  // 1 / scale picture pixels), described as describePixel() does: the same signal.
  const QString status = view->status();
  const QRegularExpression pixel(R"(pixel \((\d+), (\d+)\))");
  const QRegularExpressionMatch m = pixel.match(status);
  QVERIFY2(m.hasMatch(), qPrintable(status));
  const int a = m.captured(1).toInt(), b = m.captured(2).toInt();
  QVERIFY2(std::abs(a - u) <= 2 && std::abs(b - v) <= 2 && scale > 0.4, qPrintable(status));
  QVERIFY2(status.endsWith(view->describePixel(a, b)), qPrintable(status));
  QVERIFY2(status.contains(QString("instance %1 (%2)").arg(id).arg(about)), qPrintable(status));
  // Another frame clears it.
  view->findChild<QSpinBox*>("scanFrame")->setValue(frame == 0 ? 1 : 0);
  QVERIFY(!view->status().contains("pixel ("));
}

// The Scene tab shows the tiles the environment streams around a chainage: every triangle of
// them drawn, each in its part's class colour when coloured by class, and a picture that is
// not sky alone; an edit of the plan marks the scene out of date.
void StudioGuiTest::theSceneAroundAChainageIsWhatTheEnvironmentStreams() {
  MainWindow& w = *window_;
  trainsim::studio::SceneView* view = w.scene();
  w.viewTabs()->setCurrentWidget(view);
  QSignalSpy shown(view, &trainsim::studio::SceneView::sceneShown);
  auto* colours = view->findChild<QComboBox*>("sceneColour");
  QVERIFY(colours);
  colours->setCurrentIndex(1);  // classes
  view->showScene(300.0, 150.0);
  QVERIFY(shown.wait(120000));
  const auto plan = w.plan();
  const auto stage = trainsim::sim::makeEnvironment(*plan->plan, *plan->scenario);
  const auto at = stage->railway->frame(0, 300.0).position;
  const auto tiles = stage->environment->stream(16)->window(at, 150.0).tiles;
  QCOMPARE(view->tileCount(), static_cast<int>(tiles.size()));
  // The triangles in the order the view lays them out: tile by tile, object by object.
  long long k = 0;
  for (const auto& tile : tiles)
    for (const auto& object : tile->objects)
      for (const auto& part : object.mesh->parts)
        for (std::uint32_t t = 0; t < part.triangle_count; ++t, ++k)
          if (k % 101 == 0 &&
              view->triangleColour(k) != trainsim::scene::semanticClass(part.cls).colour)
            QFAIL(qPrintable(QString("triangle %1 not in its class's colour").arg(k)));
  QVERIFY(k > 10000);
  QCOMPARE(view->triangleCount(), k);
  QCOMPARE(view->drawnTriangles(), k);
  const QImage picture = view->grabImage();
  const QRgb sky = picture.pixel(picture.width() / 2, 2);
  int drawn = 0;
  for (int y = 0; y < picture.height(); y += 8)
    for (int x = 0; x < picture.width(); x += 8)
      drawn += picture.pixel(x, y) != sky;
  QVERIFY2(drawn > (picture.width() / 8) * (picture.height() / 8) / 3,
           qPrintable(QString("%1 of the sampled pixels drawn").arg(drawn)));
  colours->setCurrentIndex(0);
  QCOMPARE(view->drawnTriangles(), k);
  // An edit re-plans; the scene shown is then out of date until the next Show.
  QSignalSpy planned(&w, &MainWindow::planShown);
  typeInto(w, "train.body.roof_m", "3.9");
  QVERIFY(planned.wait(60000));
  QVERIFY2(view->status().contains("the plan changed"), qPrintable(view->status()));
  w.document()->undoStack()->undo();
  QVERIFY(planned.wait(60000));
  // A build of the new plan (its environment and 2 km of tiles: seconds) stopped at once:
  // it ends without drawing, says so, and the scene shown before stays.
  view->showScene(3000.0, 2000.0);
  auto* stop = view->findChild<QPushButton*>("sceneStop");
  QVERIFY(stop && stop->isEnabled());
  QTest::mouseClick(stop, Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(!view->building(), 60000);
  QTest::qWait(100);  // the finished signal's handler runs on the event loop
  QVERIFY2(view->status().contains("stopped"), qPrintable(view->status()));
  QVERIFY(!stop->isEnabled());
  QCOMPARE(view->triangleCount(), k);
}

void StudioGuiTest::screenshots() {
  const QString dir = qEnvironmentVariable("TRAINSIM_SCREENSHOT_DIR");
  if (dir.isEmpty())
    QSKIP("TRAINSIM_SCREENSHOT_DIR not set");
  MainWindow& w = *window_;
  QSignalSpy shown(&w, &MainWindow::planShown);
  w.document()->newDefault();
  QVERIFY(shown.wait(60000));
  QSignalSpy done(w.runner(), &trainsim::studio::RunController::finished);
  QVERIFY(w.startRun(tmp_.filePath("shots"), false));
  QVERIFY(done.wait(300000));
  w.inertial()->showView("IMU imu: accelerometer vs truth");
  const double t = 0.35 * w.plan()->duration_s;
  QTest::mouseClick(w.inertial()->plots()->plotWidget(), Qt::LeftButton, {},
                    w.inertial()->plots()->pixelOf(0, t));
  w.viewTabs()->setCurrentIndex(0);
  w.form()->reveal("route.generator.radius_max_m");
  QTest::qWait(500);
  QVERIFY(w.grab().save(dir + "/studio-design-3d.png"));
  w.viewTabs()->setCurrentIndex(1);
  w.inertial()->showView("Trajectory over time");
  w.inertial()->plots()->setCursor(t);
  w.form()->reveal("sensors.imus[0].preset");
  QTest::qWait(500);
  QVERIFY(w.grab().save(dir + "/studio-plan-trajectory.png"));
  w.viewTabs()->setCurrentWidget(w.scene());
  QSignalSpy scene_shown(w.scene(), &trainsim::studio::SceneView::sceneShown);
  w.scene()->showScene(1760.0, 250.0);
  QVERIFY(scene_shown.wait(120000));
  QTest::qWait(500);
  QVERIFY(w.grab().save(dir + "/studio-scene.png"));
  w.viewTabs()->setCurrentWidget(w.scans());
  w.scans()->setFrame(120);
  w.scans()->setOverlay(true);
  QTest::qWait(500);
  QVERIFY(w.grab().save(dir + "/studio-scans.png"));
}
