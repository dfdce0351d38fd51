#include "trainsim/terrain/railway.hpp"

#include "plan_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "trainsim/core/cancel.hpp"

namespace trainsim::terrain {

Railway::Railway(const track::Route& route, const track::Layout& layout,
                 const Eigen::Vector3d& shift)
    : route_(route), main_(route.track), layout_(layout), shift_(shift) {
  for (const auto& t : layout.tracks) {
    for (const auto& run : t.runs) {
      throwIfCancelled();
      const track::Polyline line = track::samplePolyline(main_, t, run.x0, run.x1);
      RunBox box{t.id, run.x0, run.x1,
                 Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()),
                 Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity())};
      for (const auto& p : line.points) {
        const Eigen::Vector2d q = (p + shift_).head<2>();
        box.lo = box.lo.cwiseMin(q);
        box.hi = box.hi.cwiseMax(q);
      }
      boxes_.push_back(box);
    }
  }
  for (const track::Block& b : route.blocks)
    if (b.type == track::BlockType::kBridge || b.type == track::BlockType::kTunnel ||
        b.type == track::BlockType::kStation)
      structures_.push_back({b.type, b.id, b.chainage_begin_m, b.chainage_end_m,
                             frame(0, b.chainage_begin_m).position.head<2>(),
                             frame(0, b.chainage_end_m).position.head<2>()});
}

std::vector<Stretch> Railway::stretchesNear(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                            double margin) const {
  std::vector<Stretch> out;
  for (const RunBox& box : boxes_) {
    if (box.lo.x() > hi.x() + margin || box.hi.x() < lo.x() - margin ||
        box.lo.y() > hi.y() + margin || box.hi.y() < lo.y() - margin)
      continue;
    if (!out.empty() && out.back().track == box.track && out.back().x1 == box.x0)
      out.back().x1 = box.x1;
    else
      out.push_back({box.track, box.x0, box.x1});
  }
  return out;
}

track::Polyline Railway::polyline(const Stretch& stretch) const {
  track::Polyline line =
      track::samplePolyline(main_, layout_.tracks.at(stretch.track), stretch.x0, stretch.x1);
  for (auto& p : line.points)
    p += shift_;
  return line;
}

track::TrackFrame Railway::frame(int track, double main_chainage_m) const {
  track::TrackFrame f = track::trackFrame(main_, layout_.tracks.at(track), main_chainage_m);
  f.position += shift_;
  return f;
}

track::LayoutBlockType Railway::typeAt(int track, double distance_m) const {
  const auto& blocks = layout_.tracks.at(track).blocks;
  const auto it =
      std::upper_bound(blocks.begin(), blocks.end(), distance_m,
                       [](double d, const track::LayoutBlock& b) { return d < b.begin_m; });
  if (it == blocks.begin())
    return blocks.empty() ? track::LayoutBlockType::kStraight : blocks.front().type;
  return std::prev(it)->type;
}

TrackDistance::TrackDistance(const Railway& railway, const Eigen::Vector2d& lo,
                             const Eigen::Vector2d& hi, double reach, double cell_m)
    : lo_(lo - Eigen::Vector2d::Constant(reach)), reach_(reach), cell_(cell_m) {
  const Eigen::Vector2d size = hi - lo + Eigen::Vector2d::Constant(2.0 * reach);
  nx_ = std::max(1, static_cast<int>(std::ceil(size.x() / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(size.y() / cell_)));
  cells_.resize(static_cast<std::size_t>(nx_) * ny_);
  for (const Stretch& s : railway.stretchesNear(lo, hi, reach)) {
    const track::Polyline line = railway.polyline(s);
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k) {
      const Segment seg{line.points[k].head<2>(), line.points[k + 1].head<2>()};
      const Eigen::Vector2d a = seg.a.cwiseMin(seg.b) - Eigen::Vector2d::Constant(reach) - lo_;
      const Eigen::Vector2d b = seg.a.cwiseMax(seg.b) + Eigen::Vector2d::Constant(reach) - lo_;
      const int c0 = std::max(0, static_cast<int>(std::floor(a.x() / cell_)));
      const int c1 = std::min(nx_ - 1, static_cast<int>(std::floor(b.x() / cell_)));
      const int r0 = std::max(0, static_cast<int>(std::floor(a.y() / cell_)));
      const int r1 = std::min(ny_ - 1, static_cast<int>(std::floor(b.y() / cell_)));
      if (c0 > c1 || r0 > r1)
        continue;
      const auto id = static_cast<std::uint32_t>(segments_.size());
      segments_.push_back(seg);
      for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c)
          cells_[static_cast<std::size_t>(r) * nx_ + c].push_back(id);
    }
  }
}

double TrackDistance::operator()(double x, double y) const {
  const int c = static_cast<int>(std::floor((x - lo_.x()) / cell_));
  const int r = static_cast<int>(std::floor((y - lo_.y()) / cell_));
  double best = std::numeric_limits<double>::infinity();
  if (c < 0 || r < 0 || c >= nx_ || r >= ny_)
    return best;
  for (const std::uint32_t id : cells_[static_cast<std::size_t>(r) * nx_ + c]) {
    const Segment& s = segments_[id];
    double t = 0.0;
    best = std::min(best, detail::segmentDistance(x, y, s.a.x(), s.a.y(), s.b.x(), s.b.y(), t));
  }
  return best <= reach_ ? best : std::numeric_limits<double>::infinity();
}

}  // namespace trainsim::terrain
