// Where a scan's rays come from: each column's pose at its firing along the trajectory, its ray
// frame and deskewing (by lane), the beams' reach past the vehicle's own body, and the rays
// themselves, filled into Embree's packets (one ray a pulse) or spread over the beam's footprint
// (several).
#include <algorithm>
#include <cmath>

#include "column_frames.hpp"
#include "trainsim/lidar/lidar.hpp"

namespace trainsim::lidar {

using detail::kDeskew;
using detail::kFrameFields;
using detail::kOrigin;
using detail::kPoseStep;
using detail::kRot;
using detail::kShift;

double Scanner::reach(const Eigen::Vector3d& direction, const Eigen::Vector3d& from) const {
  const double limit = params_.pattern.range_max_m;
  if (!params_.vehicle)
    return limit;
  // Where the ray enters the box, by the slab test in the vehicle's axes (the sensor is
  // outside it, so the entry is the first point of the vehicle on the ray).
  const Eigen::AlignedBox3d& box = params_.vehicle->box;
  const Eigen::Vector3d o = params_.vehicle->sensor_pose * from;
  const Eigen::Vector3d d = params_.vehicle->sensor_pose.linear() * direction;
  double enter = 0.0, leave = limit;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < box.min()[k] || o[k] > box.max()[k])
        return limit;
      continue;
    }
    double a = (box.min()[k] - o[k]) / d[k], b = (box.max()[k] - o[k]) / d[k];
    if (a > b)
      std::swap(a, b);
    enter = std::max(enter, a);
    leave = std::min(leave, b);
    if (enter > leave)
      return limit;
  }
  // Cut at the body (nothing of it returns; what lies before it still does, unless nearer than
  // the minimum range).
  return enter;
}

void Scanner::pulseRays(int laser, std::size_t begin, std::size_t end,
                        const Eigen::Isometry3d* poses, const Eigen::Vector3d& origin,
                        Ray* out) const {
  const ScanPattern& p = params_.pattern;
  const auto t_far = static_cast<float>(p.range_max_m);
  const std::size_t n = footprint_.size();  // several (one ray a pulse: fillPackets())
  for (std::size_t c = begin; c < end; ++c) {
    const Eigen::Isometry3d& T = poses[c];
    // The beam's origin (Scanner::origin()), shared by its sub-rays.
    const Eigen::Vector3d b = this->origin(static_cast<int>(c), laser);
    const Eigen::Vector3f o = (origins_.empty() ? Eigen::Vector3d(T.translation() - origin)
                                                : Eigen::Vector3d(T * b - origin))
                                  .cast<float>();
    const Eigen::Vector3d& d = direction(static_cast<int>(c), laser);
    // Across the beam: v horizontal (azimuth increasing), u = d × v (elevation increasing).
    Eigen::Vector3d v(-d.y(), d.x(), 0.0);
    v = v.norm() > 1e-9 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d u = d.cross(v);
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector2d& f = footprint_[k];
      const double angle = f.norm();
      const Eigen::Vector3d sub =
          angle == 0.0 ? d
                       : Eigen::Vector3d(std::cos(angle) * d +
                                         std::sin(angle) / angle * (f.x() * v + f.y() * u));
      out[(c - begin) * n + k] = {o, (T.linear() * sub).cast<float>().normalized(), 0.0f,
                                  params_.vehicle ? static_cast<float>(reach(sub, b)) : t_far};
    }
  }
}

std::vector<Ray> Scanner::rays(const RayScene& scene, const PoseAt& pose) const {
  const auto W = static_cast<std::size_t>(params_.pattern.columns);
  const std::size_t per_ring = W * footprint_.size();
  std::vector<Ray> out(ring_lasers_.size() * per_ring);
  std::vector<Eigen::Isometry3d> poses(W);
  const Eigen::Isometry3d frame_pose = pose(0.0);
  columnPoses(pose, frame_pose, 0, params_.pattern.columns, poses.data());
  if (footprint_.size() > 1) {
    for (std::size_t r = 0; r < ring_lasers_.size(); ++r)
      pulseRays(ring_lasers_[r], 0, W, poses.data(), scene.origin(), &out[r * per_ring]);
    return out;
  }
  // As castPulses() makes them.
  std::vector<float> frames(kFrameFields * padded_);
  columnFrames(poses.data(), frame_pose.inverse(), scene.origin(), 0, W, frames.data());
  std::vector<RayPacket> packets(padded_ / 8);
  for (std::size_t r = 0; r < ring_lasers_.size(); ++r) {
    fillPackets(ring_lasers_[r], 0, W, frames.data(), packets.data());
    for (std::size_t c = 0; c < W; ++c) {
      const RayPacket& q = packets[c / 8];
      const std::size_t k = c % 8;
      out[r * per_ring + c] = {{q.org_x[k], q.org_y[k], q.org_z[k]},
                               {q.dir_x[k], q.dir_y[k], q.dir_z[k]},
                               q.t_near[k],
                               q.t_far[k]};
    }
  }
  return out;
}

void Scanner::columnFrames(const Eigen::Isometry3d* poses, const Eigen::Isometry3d& world_to_frame,
                           const Eigen::Vector3d& origin, std::size_t begin, std::size_t end,
                           float* frames) const {
  const std::size_t padded = padded_;
  for (std::size_t c = begin; c < end; ++c) {
    const Eigen::Isometry3d& T = poses[c - begin];
    const Eigen::Matrix3f rot = T.linear().cast<float>();
    const Eigen::Vector3f o = (T.translation() - origin).cast<float>();
    const Eigen::Isometry3f deskew = (world_to_frame * T).cast<float>();
    for (std::size_t i = 0; i < 3; ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      for (std::size_t j = 0; j < 3; ++j) {
        const auto col = static_cast<Eigen::Index>(j);
        frames[(kRot + 3 * i + j) * padded + c] = rot(row, col);
        frames[(kDeskew + 3 * i + j) * padded + c] = deskew.linear()(row, col);
      }
      frames[(kOrigin + i) * padded + c] = o[row];
      frames[(kShift + i) * padded + c] = deskew.translation()[row];
    }
  }
}

void Scanner::fillPackets(int laser, std::size_t begin, std::size_t end, const float* frames,
                          RayPacket* out) const {
  const std::size_t P = padded_, L = ring_lasers_.size(), l = static_cast<std::size_t>(laser);
  const float* __restrict ax = &beams_[l * P];
  const float* __restrict ay = &beams_[(L + l) * P];
  const float* __restrict az = &beams_[(2 * L + l) * P];
  const float* __restrict reach = &beams_[(3 * L + l) * P];
  const bool offset = !origins_.empty();
  const float* __restrict ox = offset ? &beams_[(4 * L + l) * P] : nullptr;
  const float* __restrict oy = offset ? &beams_[(5 * L + l) * P] : nullptr;
  const float* __restrict oz = offset ? &beams_[(6 * L + l) * P] : nullptr;
  const float* __restrict f = frames;
  // Whole packets: begin is a multiple of 8 and the tables are padded to one. Eight lanes at a
  // time in Eigen's arrays (vector code).
  using F8 = Eigen::Array<float, 8, 1>;
  const auto lanes = [](const float* from) { return Eigen::Map<const F8>(from); };
  const auto into = [](float* to) { return Eigen::Map<F8, Eigen::Aligned32>(to); };
  for (std::size_t c0 = begin; c0 < end; c0 += 8) {
    RayPacket& q = out[(c0 - begin) / 8];
    const auto field = [&](std::size_t k) { return lanes(f + k * P + c0); };
    const F8 x = lanes(ax + c0), y = lanes(ay + c0), z = lanes(az + c0);
    if (offset) {  // from where the beam leaves the head, turned into world axes
      const F8 bx = lanes(ox + c0), by = lanes(oy + c0), bz = lanes(oz + c0);
      into(q.org_x) =
          field(kOrigin) + (field(kRot) * bx + field(kRot + 1) * by + field(kRot + 2) * bz);
      into(q.org_y) =
          field(kOrigin + 1) + (field(kRot + 3) * bx + field(kRot + 4) * by + field(kRot + 5) * bz);
      into(q.org_z) =
          field(kOrigin + 2) + (field(kRot + 6) * bx + field(kRot + 7) * by + field(kRot + 8) * bz);
    } else {
      into(q.org_x) = field(kOrigin);
      into(q.org_y) = field(kOrigin + 1);
      into(q.org_z) = field(kOrigin + 2);
    }
    into(q.dir_x) = field(kRot) * x + field(kRot + 1) * y + field(kRot + 2) * z;
    into(q.dir_y) = field(kRot + 3) * x + field(kRot + 4) * y + field(kRot + 5) * z;
    into(q.dir_z) = field(kRot + 6) * x + field(kRot + 7) * y + field(kRot + 8) * z;
    into(q.t_near) = F8::Zero();  // a surface nearer than the minimum range still blocks
    into(q.t_far) = lanes(reach + c0);
  }
}

void Scanner::columnPoses(const PoseAt& pose, const Eigen::Isometry3d& frame_pose, int begin,
                          int end, Eigen::Isometry3d* out) const {
  if (!params_.motion_distortion) {
    std::fill(out, out + (end - begin), frame_pose);
    return;
  }
  // The pose is asked for at every kPoseStep-th column and interpolated in between (position
  // linearly, attitude by normalised quaternion interpolation): over 16 columns (0.8 ms at
  // 10 Hz × 2048) a train's motion is a straight line and a turn of a few 1e-5 rad, so the
  // columns' poses are those of the trajectory to far below a micrometre, without a slerp and
  // a rotation matrix per column. The anchors are fixed columns, so the result does not depend
  // on how the columns are split into tasks. The last group's far anchor is the scan's end
  // (`pose` need not know the poses beyond it: the run's does not).
  const ScanPattern& pattern = params_.pattern;
  const int columns = pattern.columns;
  int anchor = -1, last = -1;
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), z = a;
  Eigen::Quaterniond qa = Eigen::Quaterniond::Identity(), qz = qa;
  for (int c = begin; c < end; ++c) {
    const int first = c / kPoseStep * kPoseStep;
    if (first != anchor) {
      anchor = first;
      last = std::min(first + kPoseStep, columns);
      a = pose(pattern.columnTime(first));
      z = pose(pattern.columnTime(last));
      qa = Eigen::Quaterniond(a.linear());
      qz = Eigen::Quaterniond(z.linear());
      if (qa.dot(qz) < 0.0)
        qz.coeffs() = -qz.coeffs();
    }
    const int k = c - first;
    if (k == 0) {
      *out++ = a;
      continue;
    }
    const double u = static_cast<double>(k) / (last - first);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = (1.0 - u) * a.translation() + u * z.translation();
    T.linear() = Eigen::Quaterniond((1.0 - u) * qa.coeffs() + u * qz.coeffs())
                     .normalized()
                     .toRotationMatrix();
    *out++ = T;
  }
}

}  // namespace trainsim::lidar
