#pragma once

#include <QImage>
#include <QWidget>
#include <memory>

#include "plan_service.hpp"

namespace trainsim::studio {

/// The 3D design view (VTK): every track coloured by block type, chainage labels along the
/// main track, a marker at each design-rule violation, and the train where a plot's time
/// cursor puts it. Later views (terrain, objects, point clouds) add actors to the same scene.
class DesignView3D : public QWidget {
  Q_OBJECT

 public:
  explicit DesignView3D(QWidget* parent = nullptr);
  ~DesignView3D() override;

  void setPlan(std::shared_ptr<const PlanSnapshot> plan);
  /// Shows the train at `pose` (hidden until the first call).
  void markTrain(const TrainPose& pose);

  /// What the scene holds, for tests: line segments drawn, violation markers, chainage labels.
  int segmentCount() const;
  int violationCount() const;
  int labelCount() const;
  bool trainVisible() const;
  /// The train marker's centre in world coordinates.
  Eigen::Vector3d trainPosition() const;
  /// The rendered view as an image (for screenshots).
  QImage grabImage();

 private:
  struct Impl;
  std::unique_ptr<Impl> d_;
};

}  // namespace trainsim::studio
