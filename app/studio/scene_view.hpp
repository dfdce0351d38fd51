#pragma once

#include <QImage>
#include <QWidget>
#include <array>
#include <cstdint>
#include <memory>

#include "plan_service.hpp"
#include "scene_polydata.hpp"

namespace trainsim::studio {

/// The planned scene around a chainage of the main track: the terrain, track assets, structures
/// and trackside objects of every tile within a radius, coloured as the cameras see them
/// (materials) or as the labels have them (classes). Built from the current plan off the GUI
/// thread when asked (Show), so editing never waits for terrain; an edit marks it out of date.
class SceneView : public QWidget {
  Q_OBJECT

 public:
  explicit SceneView(QWidget* parent = nullptr);
  ~SceneView() override;

  /// The plan to build scenes from (the one shown stays until the next Show).
  void setPlan(std::shared_ptr<const PlanSnapshot> plan);
  /// Builds the scene within `radius_m` of main chainage `chainage_m` of the current plan;
  /// sceneShown() when it is drawn. A newer request replaces one still building, which stops.
  void showScene(double chainage_m, double radius_m);
  /// Stops the build still running (Stop): within a tile's or a plan stage's time, it ends
  /// with "stopped" in the status line and the scene shown before stays.
  void stopBuild();
  bool building() const;
  void setColour(app::SceneColour colour);

  int tileCount() const;
  /// Triangles of the tiles shown, and those in the drawn poly data with their colours.
  long long triangleCount() const;
  long long drawnTriangles() const;
  std::array<std::uint8_t, 3> triangleColour(long long i) const;
  /// The tiles shown (for tests: the scene's own tiles, as a run streams them).
  const std::vector<std::shared_ptr<const scene::Tile>>& tiles() const;
  QString status() const;
  QImage grabImage();

 signals:
  void sceneShown();

 private:
  void draw();
  void showStatus();

  struct Impl;
  std::unique_ptr<Impl> d_;
};

}  // namespace trainsim::studio
