#pragma once

#include <QImage>
#include <QString>
#include <QStringList>
#include <QWidget>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace trainsim::studio {

/// A generated dataset's perception output, frame by frame: a LiDAR's scan
/// (velodyne/NNNNNN.bin and labels/NNNNNN.label, read as KITTI and SemanticKITTI define them)
/// as a point cloud coloured by class, instance, intensity or height, the frame's points per
/// class, and a camera's picture beside it (RGB, semantic in the classes' colours, depth, or
/// instances), optionally with the scan's points drawn on it where they project through
/// calib.txt (Tr or Tr_N into camera 0's frame, then the camera's P and its lens's D), in the
/// colours the scan is drawn in. Files that disagree (a .label whose length is not the .bin's,
/// a calib.txt without the lines the pair needs) are reported in the view's status line, not
/// drawn. A click on the picture says what is there (describePixel()).
class ScanView : public QWidget {
  Q_OBJECT

 public:
  enum class Colour { kClass, kInstance, kIntensity, kHeight };
  enum class Picture { kRgb, kSemantic, kDepth, kInstance };

  explicit ScanView(QWidget* parent = nullptr);
  ~ScanView() override;

  /// Shows the dataset in `root` (its manifest's sequence folder): every velodyne[_N]/ and
  /// image_N/ folder found, from frame 0. Returns false (and says why in the status line) when
  /// it has neither.
  bool setDataset(const QString& root);
  void setFrame(int frame);
  void setLidar(int index);
  void setCamera(int index);
  void setColour(Colour colour);
  void setPicture(Picture picture);
  /// Draws the scan's points on the picture (off at first).
  void setOverlay(bool on);

  /// A point of the scan as it projects into the camera: its pixel (KITTI's convention: pixel
  /// centres at whole numbers), its depth along the camera's optical axis, and its index in
  /// the scan.
  struct Projected {
    double u = 0.0, v = 0.0, depth = 0.0;
    int point = 0;
  };
  /// The scan's points that project into the shown picture (in front of the camera, inside the
  /// image), far first; empty when there is no scan, picture or calibration for the pair.
  std::vector<Projected> projected() const;

  int frameCount() const;
  int frame() const;
  QStringList lidars() const;   ///< the LiDAR folders found: velodyne, velodyne_1, …
  QStringList cameras() const;  ///< the camera folders found: image_2, image_3, …
  /// The scan shown: its points, the colour each is drawn in, and its points per class id.
  int pointCount() const;
  std::array<std::uint8_t, 3> pointColour(int i) const;
  std::map<int, int> classCounts() const;
  /// The camera picture shown (null when the frame has none), and the status line.
  QImage picture() const;
  QString status() const;
  /// What the shown camera saw at pixel (u, v) of the frame, from its semantic, instance and
  /// depth images and instances.csv (those of them the dataset has): the class, the object's
  /// instance id with its track and state (a signal's aspect), the depth. Empty outside the
  /// picture. A click on the picture puts it in the status line.
  QString describePixel(int u, int v) const;
  /// The rendered point cloud (for screenshots).
  QImage grabImage();

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 public:
  /// The colours the view draws with: the class table's (unlabelled in grey, unknown ids in
  /// white), and a dark-blue → teal → yellow ramp over [0, 1] (intensity, height, depth).
  static std::array<std::uint8_t, 3> classColour(std::uint32_t id);
  static std::array<std::uint8_t, 3> ramp(double t);

 private:
  void loadScan();
  void loadPicture();
  void recolour();
  void updateProjection();
  void composePicture();
  void showPicture();
  void showStatus();
  void showFrameControls();
  QString frameFile(const std::string& folder, const char* extension) const;

  struct Impl;
  std::unique_ptr<Impl> d_;
};

}  // namespace trainsim::studio
