#pragma once
// A camera's images of the scene, rendered with VTK into an offscreen OpenGL framebuffer (an X
// server is needed: Debian's VTK is built for GLX only; see x_display.hpp).
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "trainsim/camera/camera_model.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim::camera {

/// Which images a render makes; only those are drawn (depth comes with the colour pass, the
/// semantic and instance images from one id pass).
struct Passes {
  bool rgb = true;
  bool depth = true;
  bool semantic = true;
  bool instance = true;
};

/// A spot light carried with the camera (the train's headlights).
struct Spot {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          ///< camera frame, m
  Eigen::Vector3d direction = Eigen::Vector3d(0.0, 0.0, 1.0);  ///< camera frame, unit
  double half_angle_deg = 15.0;                                ///< the cone's
  double intensity = 1.0;
  /// The light falls off as 1 / (1 + (d / half_distance_m)²) with distance d.
  double half_distance_m = 40.0;
};

/// Light and sky of a render.
struct Lighting {
  /// Towards the sun, world frame (ENU-like: z up), unit.
  Eigen::Vector3d sun_direction = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  double sun_intensity = 1.0;
  double ambient = 0.35;                 ///< the share of the surface colour lit by the sky
  scene::Rgb sky_zenith{110, 150, 205};  ///< the background's top and horizon colours
  scene::Rgb sky_horizon{190, 210, 230};
  std::vector<Spot> spots;
};

struct RendererOptions {
  Intrinsics intrinsics;
  /// The clipping planes: nothing nearer than near_m is drawn, nothing beyond far_m (the draw
  /// distance). The depth buffer's step at z is about z² / (near · 2²⁴): 1.2 mm at 100 m for
  /// near = 0.5 m (sensors-reference.md 7.3).
  double near_m = 0.5;
  double far_m = 400.0;
  Passes passes;
  /// Draw only what meets the view frustum (off: everything in the window, the benchmark's
  /// baseline; the images are the same).
  bool cull = true;
  /// Level of detail: level L merges the vertices of a mesh in cubic cells of 5 cm · 2^(L−1)
  /// (L = 1…4; a vertex moves by at most the cell's diagonal); it is drawn where that cell, at
  /// the nearest point of the object's box, spans at most this many pixels. 0: every object at
  /// full detail.
  double lod_pixels = 1.0;
  /// Smooth the colour image's edges with FXAA (VTK's post-process on the colour pass only:
  /// depth, class and instance images stay per pixel, unblended).
  bool fxaa = false;
  /// The share of daylight reaching each of a render's world points (`shares[i]` for
  /// `points[i]`: 1 in the open, 0 deep in a tunnel; the points are the pixels' surfaces, row
  /// by row); empty: daylight everywhere. With it, render()'s `shade` lights what daylight does
  /// not reach.
  std::function<void(std::span<const Eigen::Vector3d> points, std::span<float> shares)> daylight;
  /// Whether some point of a world box may be out of full daylight (false only where the
  /// daylight function gives 1 throughout); empty: anywhere. A frame in which nothing drawn
  /// may be works out no shares.
  std::function<bool(const scene::Box3d& box)> shade_meets;
};

/// A render's images, rows top to bottom, width × height pixels each (empty if not asked for).
struct CameraImages {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 bytes a pixel
  /// Metres along the optical axis; 0 where nothing is drawn (sky, or beyond far_m).
  std::vector<float> depth;
  std::vector<std::uint8_t> semantic;  ///< class id; sky where nothing is drawn
  /// The object drawn at each pixel, 0 for none: an index into `instances`.
  std::vector<std::uint16_t> object;
  /// The scene instance id of each object value (instances[0] = 0).
  std::vector<scene::InstanceId> instances;
  std::int64_t triangles = 0;  ///< triangles drawn (each pass), after culling
  std::int64_t objects = 0;    ///< objects and wires drawn
};

/// Renders a scene window from a camera pose. The renderer owns its VTK window and OpenGL
/// context on a thread of its own, so render() may be called from any thread (calls are served
/// one at a time). Geometry is placed relative to the camera in double and drawn in float, so
/// accuracy does not depend on the distance from the scenario origin. Only objects whose boxes
/// meet the view frustum within far_m are drawn. The images are a pure function of the window
/// and the pose: draw order follows the window, never what was drawn before.
class Renderer {
 public:
  explicit Renderer(RendererOptions options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const RendererOptions& options() const { return options_; }

  /// `T_world_cam`: the camera's pose (camera axes as camera_model.hpp, world double).
  /// `shade` (optional, with RendererOptions::daylight): the lighting of surfaces no daylight
  /// reaches (a tunnel's: the lamps, no sun). Each surface of the colour image is then lit by
  /// both in proportion to the daylight share of the surface a pixel shows (its point from the
  /// id pass's depth, drawn first): the blend of what the two lightings would draw, as light is
  /// linear in the share, in one colour pass (VTK casts no shadows to do it instead). The sky
  /// is the sky either way.
  CameraImages render(const scene::SceneWindow& window, const Eigen::Isometry3d& T_world_cam,
                      const Lighting& lighting, const Lighting* shade = nullptr) const;

 private:
  struct Impl;
  RendererOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace trainsim::camera
