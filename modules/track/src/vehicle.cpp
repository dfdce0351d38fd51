#include "trainsim/track/vehicle.hpp"

#include <cmath>

#include "trainsim/core/frames.hpp"

namespace trainsim::track {
namespace {

struct PivotKinematics {
  Eigen::Vector3d p, v, a;
  double roll, roll_rate, roll_accel;
};

// A point running along the track at distance u with speed u̇ and acceleration ü:
// V = P' u̇, A = P'' u̇² + P' ü (primes: d/du), and likewise for the roll angle.
PivotKinematics pivot(const TrackPoint& t, double speed, double accel) {
  return {t.position, t.d1 * speed,      t.d2 * speed * speed + t.d1 * accel,
          t.roll_rad, t.roll_d1 * speed, t.roll_d2 * speed * speed + t.roll_d1 * accel};
}

}  // namespace

BodyState bodyState(const Track& track, const VehicleGeometry& geometry, const MotionState& m) {
  BodyState b;
  b.front_track = track.atDistance(m.u_m);
  const TrackPoint rear_track = track.atDistance(m.u_m - geometry.bogie_spacing_m);
  const PivotKinematics f = pivot(b.front_track, m.v_m_s, m.a_m_s2);
  const PivotKinematics r = pivot(rear_track, m.v_m_s, m.a_m_s2);
  b.front = f.p;
  b.rear = r.p;
  b.origin = 0.5 * (f.p + r.p);
  b.origin_v = 0.5 * (f.v + r.v);
  b.origin_a = 0.5 * (f.a + r.a);

  // Chord c and its first two time derivatives.
  const Eigen::Vector3d c = f.p - r.p;
  const Eigen::Vector3d cd = f.v - r.v;
  const Eigen::Vector3d cdd = f.a - r.a;
  const double h2 = c.x() * c.x() + c.y() * c.y();
  const double h = std::sqrt(h2);
  // ψ = atan2(c_y, c_x): ψ̇ = (c_x ċ_y − c_y ċ_x)/h², ψ̈ = (c_x c̈_y − c_y c̈_x)/h² − ψ̇ 2ḣ/h.
  const double hd = (c.x() * cd.x() + c.y() * cd.y()) / h;
  const double cross = c.x() * cd.y() - c.y() * cd.x();
  const double yaw_rate = cross / h2;
  const double yaw_acc = (c.x() * cdd.y() - c.y() * cdd.x()) / h2 - 2.0 * yaw_rate * hd / h;
  // θ = atan2(c_z, h): θ̇ = (h ċ_z − c_z ḣ)/(h² + c_z²).
  const double hdd =
      (cd.x() * cd.x() + cd.y() * cd.y() + c.x() * cdd.x() + c.y() * cdd.y()) / h - hd * hd / h;
  const double n2 = h2 + c.z() * c.z();
  const double num = h * cd.z() - c.z() * hd;
  const double pitch_rate = num / n2;
  const double num_d = h * cdd.z() - c.z() * hdd;  // (ḣ ċ_z − ċ_z ḣ) cancels
  const double n2_d = 2.0 * (h * hd + c.z() * cd.z());
  const double pitch_acc = num_d / n2 - num * n2_d / (n2 * n2);

  b.yaw_rad = std::atan2(c.y(), c.x());
  b.pitch_rad = std::atan2(c.z(), h);
  double roll_rate = 0.0, roll_acc = 0.0;
  if (geometry.wheelbase_m > 0.0) {
    const double h = geometry.wheelbase_m / 2.0;
    b.roll_rad = 0.0;
    for (const double u : {m.u_m - h, m.u_m + h, m.u_m - geometry.bogie_spacing_m - h,
                           m.u_m - geometry.bogie_spacing_m + h}) {
      const Track::Roll t = track.rollAtDistance(u);
      b.roll_rad += 0.25 * t.rad;
      roll_rate += 0.25 * t.d1 * m.v_m_s;
      roll_acc += 0.25 * (t.d2 * m.v_m_s * m.v_m_s + t.d1 * m.a_m_s2);
    }
  } else {
    b.roll_rad = 0.5 * (f.roll + r.roll);
    roll_rate = 0.5 * (f.roll_rate + r.roll_rate);
    roll_acc = 0.5 * (f.roll_accel + r.roll_accel);
  }
  b.euler_rate = {roll_rate, pitch_rate, yaw_rate};

  const double sf = std::sin(b.roll_rad), cf = std::cos(b.roll_rad);
  const double st = std::sin(b.pitch_rad), ct = std::cos(b.pitch_rad);
  b.r_world_body = attitude(b.yaw_rad, b.pitch_rad, b.roll_rad);
  // ω_body for R = Rz(ψ) Ry(−θ) Rx(φ), and its time derivative.
  const double fd = roll_rate, td = pitch_rate, pd = yaw_rate;
  b.w_body = {fd + pd * st, -td * cf + pd * ct * sf, td * sf + pd * ct * cf};
  b.alpha_body = {
      roll_acc + yaw_acc * st + pd * td * ct,
      -pitch_acc * cf + td * fd * sf + yaw_acc * ct * sf - pd * td * st * sf + pd * fd * ct * cf,
      pitch_acc * sf + td * fd * cf + yaw_acc * ct * cf - pd * td * st * cf - pd * fd * ct * sf};
  return b;
}

Eigen::Vector3d BodyState::pointPosition(const Eigen::Vector3d& r) const {
  return origin + r_world_body * r;
}

Eigen::Vector3d BodyState::pointVelocity(const Eigen::Vector3d& r) const {
  return origin_v + r_world_body * w_body.cross(r);
}

Eigen::Vector3d BodyState::pointAcceleration(const Eigen::Vector3d& r) const {
  return origin_a + r_world_body * (alpha_body.cross(r) + w_body.cross(w_body.cross(r)));
}

}  // namespace trainsim::track
