#pragma once
// A pulse's echoes with beam divergence: its sub-rays' hits grouped by range into echoes, and
// the ones the sensor reports (strongest, last or dual).
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "trainsim/lidar/lidar.hpp"
#include "trainsim/lidar/ray_scene.hpp"

namespace trainsim::lidar::detail {

// One sub-ray's hit, the sub-ray's unit direction, and its backscatter.
struct SubHit {
  const RayHit* hit;
  Eigen::Vector3f direction;
  double range;
  double rho;
};

// One echo of a pulse: sub-ray hits that follow each other in range closer than the echo
// separation, or further apart on one surface (a plane at a grazing angle stretches its echo
// over more range than the separation: one broad peak in a real receiver's waveform, not two).
struct Echo {
  double range = 0.0;             // the backscatter-weighted mean of its sub-rays' ranges
  double reflectivity = 0.0;      // Σ w ρ over its sub-rays: what the intensity reports
  double coverage = 0.0;          // Σ w: the share of the pulse that hit it
  const RayHit* label = nullptr;  // the sub-ray hit with the most backscatter
};

// Groups a pulse's sub-ray hits into echoes, nearest first (see echoes.cpp); `weight` is each
// sub-ray's share of the pulse's energy.
void echoesOf(std::vector<SubHit>& sub, double separation, double weight, std::vector<Echo>& out);

// Moves the echoes the pulse reports to the front (strongest by received power ∝ ρ / R², the
// last, or both) and returns how many; 0 when none is bright enough.
std::size_t selectReturns(std::vector<Echo>& echoes, const LidarParams& params);

}  // namespace trainsim::lidar::detail
