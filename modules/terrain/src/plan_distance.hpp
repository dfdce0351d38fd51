// Private to the terrain module: the plan distance from a point to a segment, shared by the
// height field's splatting and TrackDistance.
#pragma once

#include <algorithm>
#include <cmath>

namespace trainsim::terrain::detail {

/// Plan distance from p to the segment ab, and in `t` the parameter of the nearest point.
inline double segmentDistance(double px, double py, double ax, double ay, double bx, double by,
                              double& t) {
  const double ux = bx - ax, uy = by - ay;
  const double len2 = ux * ux + uy * uy;
  t = len2 > 0.0 ? std::clamp(((px - ax) * ux + (py - ay) * uy) / len2, 0.0, 1.0) : 0.0;
  const double dx = px - (ax + t * ux), dy = py - (ay + t * uy);
  return std::sqrt(dx * dx + dy * dy);
}

}  // namespace trainsim::terrain::detail
