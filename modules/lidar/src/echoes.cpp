#include "echoes.hpp"

#include <cmath>
#include <utility>

namespace trainsim::lidar::detail {
namespace {

// Whether `b` hit the surface `a` hit, as far as the pulse can tell: the same object and class,
// and the plane through a's hit with a's normal meets b's ray (from the same origin) within
// `separation` of where b hit. Exact for a plane at any incidence; a gently curved surface (the
// ground) passes within the separation over a footprint's width. Only one object: at a grazing
// angle the plane's prediction swings with the smallest change of direction, and a wire's hit
// must not pass for the ground behind it by chance.
bool onOneSurface(const SubHit& a, const SubHit& b, double separation) {
  if (a.hit->object != b.hit->object || a.hit->cls != b.hit->cls)
    return false;
  const Eigen::Vector3d n = a.hit->normal.cast<double>();
  const double across = n.dot(b.direction.cast<double>());
  if (std::abs(across) < 1e-9)
    return false;
  const double predicted = a.range * n.dot(a.direction.cast<double>()) / across;
  return std::abs(predicted - b.range) <= separation;
}

}  // namespace

// Groups a pulse's sub-ray hits into echoes, nearest first; `weight` is each sub-ray's share
// of the pulse's energy. One hit gives one echo at exactly its range and reflectivity. A hit
// starts a new echo when it lies more than the separation beyond the previous one and neither
// lies on the other's surface (a wire before a wall, a platform's edge before the track bed, a
// crest before the ground behind it).
void echoesOf(std::vector<SubHit>& sub, double separation, double weight, std::vector<Echo>& out) {
  // Insertion sort: stable, no allocation (a pulse has few sub-rays, most often one).
  for (std::size_t i = 1; i < sub.size(); ++i)
    for (std::size_t j = i; j > 0 && sub[j].range < sub[j - 1].range; --j)
      std::swap(sub[j], sub[j - 1]);
  out.clear();
  double near = 0.0, sum_offset = 0.0, best = -1.0;
  for (std::size_t i = 0; i < sub.size(); ++i) {
    if (i == 0 || (sub[i].range - sub[i - 1].range > separation &&
                   !onOneSurface(sub[i - 1], sub[i], separation) &&
                   !onOneSurface(sub[i], sub[i - 1], separation))) {
      out.emplace_back();
      near = sub[i].range;
      sum_offset = 0.0;
      best = -1.0;
    }
    Echo& e = out.back();
    const double backscatter = weight * sub[i].rho;
    e.reflectivity += backscatter;
    e.coverage += weight;
    sum_offset += (backscatter > 0.0 ? backscatter : 0.0) * (sub[i].range - near);
    e.range = near + (e.reflectivity > 0.0 ? sum_offset / e.reflectivity : 0.0);
    if (backscatter > best) {
      best = backscatter;
      e.label = sub[i].hit;
    }
  }
}

// Moves the echoes the pulse reports to the front (strongest by received power ∝ ρ / R², the
// last, or both) and returns how many; 0 when none is bright enough.
std::size_t selectReturns(std::vector<Echo>& echoes, const LidarParams& params) {
  std::size_t strongest = echoes.size(), last = echoes.size();
  double power = 0.0;
  const double detectable = params.detectable();
  for (std::size_t i = 0; i < echoes.size(); ++i) {
    const Echo& e = echoes[i];
    if (!(e.reflectivity > 0.0) || e.reflectivity < params.intensity_threshold)
      continue;
    const double p = e.reflectivity / (e.range * e.range);
    if (e.reflectivity < detectable * (e.range * e.range))  // as packetReturns() has it
      continue;
    if (strongest == echoes.size() || p > power) {
      strongest = i;
      power = p;
    }
    last = i;  // nearest first, so the last bright one is the farthest
  }
  if (strongest == echoes.size())
    return 0;
  const Echo s = echoes[strongest], l = echoes[last];
  switch (params.returns) {
    case LidarParams::Returns::kStrongest:
      echoes[0] = s;
      return 1;
    case LidarParams::Returns::kLast:
      echoes[0] = l;
      return 1;
    case LidarParams::Returns::kDual:
      echoes[0] = s;
      if (last == strongest)
        return 1;
      echoes[1] = l;
      return 2;
  }
  return 0;
}

}  // namespace trainsim::lidar::detail
