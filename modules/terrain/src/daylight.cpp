#include "trainsim/terrain/daylight.hpp"

#include <algorithm>
#include <cmath>

namespace trainsim::terrain {
namespace {

// Main chainage between the samples of a tunnel's track (the bore's frames in between are the
// nearest sample's, off by at most a metre along a curve of 300 m radius: a few millimetres).
constexpr double kSpacing_m = 2.0;
// Samples skipped by the coarse search for the nearest (kSpacing_m × kStride = 16 m: a curve
// of the tightest radius turns by 3° over it, so the nearest coarse sample is within a stride).
constexpr std::size_t kStride = 8;
// Margins around the bore's surfaces (the lining lies within the tube's half width and crown,
// the invert at the formation): a pixel's point from the depth buffer is off by millimetres,
// and a wall on the bore's edge must not come out half in daylight.
constexpr double kMargin_m = 0.5;

}  // namespace

TunnelDaylight::TunnelDaylight(const track::Route& route, const track::Layout& layout,
                               const TerrainParams& params, double reach_m,
                               const Eigen::Vector3d& shift)
    : reach_m_(reach_m) {
  if (layout.tracks.empty())
    return;
  const track::LayoutTrack& main = layout.tracks[0];
  for (const track::Block& b : route.blocks) {
    if (b.type != track::BlockType::kTunnel)
      continue;
    Tube tube;
    tube.begin_m = b.chainage_begin_m;
    tube.end_m = b.chainage_end_m;
    tube.crown_m = params.tunnel_crown_m + kMargin_m;
    tube.floor_m = -(params.formation_depth_m + 1.0 + kMargin_m);
    double left = 0.0, right = 0.0;  // the outermost tracks' offsets
    const auto n = static_cast<std::size_t>(std::ceil((tube.end_m - tube.begin_m) / kSpacing_m));
    for (std::size_t i = 0; i <= n; ++i) {
      const double s = std::min(tube.end_m, tube.begin_m + static_cast<double>(i) * kSpacing_m);
      const track::TrackFrame f = track::trackFrame(route.track, main, s);
      tube.samples.push_back({f.position + shift, f.tangent, f.left, f.up, s});
      for (const track::LayoutTrack& t : layout.tracks) {
        if (t.id == main.id || t.kind == track::TrackKind::kAuxiliary ||
            s < t.main_chainage_begin_m || s > t.main_chainage_end_m)
          continue;
        const double offset =
            (track::trackFrame(route.track, t, s).position - f.position).dot(f.left);
        left = std::max(left, offset);
        right = std::min(right, offset);
      }
    }
    tube.left_m = left + params.tunnel_half_width_m + kMargin_m;
    tube.right_m = right - params.tunnel_half_width_m - kMargin_m;
    const double across = std::max(tube.left_m, -tube.right_m);
    tube.radius_m = std::hypot(across, std::max(tube.crown_m, -tube.floor_m)) + kSpacing_m;
    for (const Sample& q : tube.samples) {
      tube.box.extend(q.position + across * q.left + tube.crown_m * q.up);
      tube.box.extend(q.position - across * q.left + tube.floor_m * q.up);
      tube.box.extend(q.position + across * q.left + tube.floor_m * q.up);
      tube.box.extend(q.position - across * q.left + tube.crown_m * q.up);
    }
    tubes_.push_back(std::move(tube));
  }
}

double TunnelDaylight::share(const Tube& tube, const Eigen::Vector3d& world,
                             std::size_t& hint) const {
  if (!tube.box.contains(world))
    return -1.0;
  const auto distance2 = [&](std::size_t j) {
    return (world - tube.samples[j].position).squaredNorm();
  };
  const std::size_t last = tube.samples.size() - 1;
  // Downhill from the hint: a point near the track has one nearest sample, and a picture's
  // next pixel is most often nearest the same one or its neighbour.
  std::size_t best = std::min(hint, last);
  double d2 = distance2(best);
  while (best < last && distance2(best + 1) < d2)
    d2 = distance2(++best);
  while (best > 0 && distance2(best - 1) < d2)
    d2 = distance2(--best);
  // Past an end of the tube (in front of a portal): outside the bore.
  const double along = (world - tube.samples[best].position).dot(tube.samples[best].tangent);
  if ((best == 0 && along < 0.0) || (best == last && along > 0.0)) {
    hint = best;
    return -1.0;
  }
  // Not the foot of the perpendicular (a local nearest far along a curve): the coarse search,
  // then its neighbourhood.
  if (std::abs(along) > kSpacing_m) {
    best = 0;
    for (std::size_t j = 0; j <= last; j += kStride)
      if (distance2(j) < distance2(best))
        best = j;
    const std::size_t lo = best > kStride ? best - kStride : 0;
    const std::size_t hi = std::min(last, best + kStride);
    for (std::size_t j = lo; j <= hi; ++j)
      if (distance2(j) < distance2(best))
        best = j;
  }
  hint = best;
  const Sample& q = tube.samples[best];
  const Eigen::Vector3d d = world - q.position;
  const double s = q.chainage_m + d.dot(q.tangent);
  const double across = d.dot(q.left), up = d.dot(q.up);
  if (s <= tube.begin_m || s >= tube.end_m || across > tube.left_m || across < tube.right_m ||
      up > tube.crown_m || up < tube.floor_m)
    return -1.0;
  const double inside = std::min(s - tube.begin_m, tube.end_m - s);
  return std::clamp(1.0 - inside / reach_m_, 0.0, 1.0);
}

double TunnelDaylight::operator()(const Eigen::Vector3d& world) const {
  for (const Tube& tube : tubes_) {
    std::size_t hint = 0;
    if (const double w = share(tube, world, hint); w >= 0.0)
      return w;
  }
  return 1.0;
}

bool TunnelDaylight::meets(const scene::Box3d& box) const {
  if (box.empty())
    return false;
  const Eigen::AlignedBox3d b(box.min, box.max);
  for (const Tube& tube : tubes_) {
    if (!tube.box.intersects(b))
      continue;
    for (const Sample& q : tube.samples)
      if (b.squaredExteriorDistance(q.position) <= tube.radius_m * tube.radius_m)
        return true;
  }
  return false;
}

void TunnelDaylight::shares(std::span<const Eigen::Vector3d> world, std::span<float> out) const {
  std::vector<std::size_t> hints(tubes_.size(), 0);
  for (std::size_t i = 0; i < world.size(); ++i) {
    out[i] = 1.0f;
    for (std::size_t t = 0; t < tubes_.size(); ++t)
      if (const double w = share(tubes_[t], world[i], hints[t]); w >= 0.0) {
        out[i] = static_cast<float>(w);
        break;
      }
  }
}

}  // namespace trainsim::terrain
