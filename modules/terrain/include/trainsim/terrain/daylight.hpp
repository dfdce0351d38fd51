#pragma once
// How much daylight reaches a point of the scene: the cameras' tunnels.
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "trainsim/scene/mesh.hpp"
#include "trainsim/terrain/terrain.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/route.hpp"

namespace trainsim::terrain {

/// The share of daylight (the sun's and the sky's light) that reaches a point: 1 in the open,
/// falling linearly from a tunnel's portal to 0 at `reach_m` inside its bore. The bore is the
/// tube's space: past a portal along the main track, within `tunnel_half_width_m` beyond the
/// outermost tracks through the tunnel, between the formation and `tunnel_crown_m` (with half a
/// metre's margin, so that the lining on the tube's edge is never half out of it). A look,
/// not light transport (the renderer draws no shadows), so that a tunnel seen from outside is
/// dark inside and the world seen from inside lit, as a per-surface factor rather than one for
/// the whole picture. Immutable; thread-safe.
class TunnelDaylight {
 public:
  static constexpr double kReach_m = 50.0;

  /// The main track's tunnel blocks of `route`, their tracks from `layout`; points are world
  /// coordinates moved by `shift` (as terrain::Railway's).
  TunnelDaylight(const track::Route& route, const track::Layout& layout,
                 const TerrainParams& params, double reach_m = kReach_m,
                 const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

  /// No tunnel: daylight everywhere.
  bool empty() const { return tubes_.empty(); }
  /// The share of daylight at a world point, 0..1.
  double operator()(const Eigen::Vector3d& world) const;
  /// Whether some point of a world box may be out of full daylight: false only where the
  /// share is 1 all over the box (conservative: a box near a bore's end may still be all day).
  bool meets(const scene::Box3d& box) const;
  /// The shares at many points (`out[i]` for `world[i]`): the same numbers, faster for points
  /// near each other in turn (a picture's pixels row by row), whose nearest track samples are
  /// looked for from the previous point's.
  void shares(std::span<const Eigen::Vector3d> world, std::span<float> out) const;

 private:
  struct Sample {
    Eigen::Vector3d position, tangent, left, up;
    double chainage_m = 0.0;
  };
  struct Tube {
    double begin_m = 0.0, end_m = 0.0;    // main chainage of the portals
    double left_m = 0.0, right_m = 0.0;   // the bore's sides from the main track (+ left)
    double crown_m = 0.0, floor_m = 0.0;  // the bore's top and bottom over the rails
    Eigen::AlignedBox3d box;              // every point of the bore lies in it
    double radius_m = 0.0;                // no point of the bore is farther from its nearest sample
    std::vector<Sample> samples;
  };
  // The share at `world` in `tube`, or none (−1) outside its bore; `hint`: the sample to look
  // for the nearest from, set to the nearest found.
  double share(const Tube& tube, const Eigen::Vector3d& world, std::size_t& hint) const;

  std::vector<Tube> tubes_;
  double reach_m_;
};

}  // namespace trainsim::terrain
