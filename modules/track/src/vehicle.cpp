#include "trainsim/track/vehicle.hpp"

#include <cmath>

#include "trainsim/core/frames.hpp"

namespace trainsim::track {
namespace {

// Second-order jets in time: a quantity with its first two time derivatives, so the body's
// attitude, rate and angular acceleration follow from the pivots' motion by the product and
// chain rules, exactly, whatever the frame the track is laid in.
struct Scalar {
  double v, d, dd;
};
struct Vec {
  Eigen::Vector3d v, d, dd;
};
Vec operator+(const Vec& a, const Vec& b) {
  return {a.v + b.v, a.d + b.d, a.dd + b.dd};
}
Vec operator-(const Vec& a, const Vec& b) {
  return {a.v - b.v, a.d - b.d, a.dd - b.dd};
}
Vec operator*(const Scalar& a, const Vec& x) {
  return {a.v * x.v, a.d * x.v + a.v * x.d, a.dd * x.v + 2.0 * a.d * x.d + a.v * x.dd};
}
Vec cross(const Vec& a, const Vec& b) {
  return {a.v.cross(b.v), a.d.cross(b.v) + a.v.cross(b.d),
          a.dd.cross(b.v) + 2.0 * a.d.cross(b.d) + a.v.cross(b.dd)};
}
Vec normalized(const Vec& a) {
  const double r = a.v.norm();
  const double rd = a.v.dot(a.d) / r;
  const double rdd = (a.d.dot(a.d) + a.v.dot(a.dd)) / r - rd * rd / r;
  const Scalar inv{1.0 / r, -rd / (r * r), -rdd / (r * r) + 2.0 * rd * rd / (r * r * r)};
  return inv * a;
}
Scalar sin(const Scalar& a) {
  return {std::sin(a.v), std::cos(a.v) * a.d, -std::sin(a.v) * a.d * a.d + std::cos(a.v) * a.dd};
}
Scalar cos(const Scalar& a) {
  return {std::cos(a.v), -std::sin(a.v) * a.d, -std::cos(a.v) * a.d * a.d - std::sin(a.v) * a.dd};
}

// A point running along the track at distance u with speed u̇ and acceleration ü:
// V = P' u̇, A = P'' u̇² + P' ü (primes: d/du); likewise the local vertical.
Vec along(const Eigen::Vector3d& x, const Eigen::Vector3d& x_u, const Eigen::Vector3d& x_uu,
          const MotionState& m) {
  return {x, x_u * m.v_m_s, x_uu * m.v_m_s * m.v_m_s + x_u * m.a_m_s2};
}

// Local east and north at a track point, from its horizontal tangent and left vectors.
std::pair<Eigen::Vector3d, Eigen::Vector3d> eastNorth(const TrackPoint& t) {
  const Eigen::Vector3d th = t.left.cross(t.up);
  const double c = std::cos(t.heading_rad), s = std::sin(t.heading_rad);
  return {c * th - s * t.left, s * th + c * t.left};
}

}  // namespace

BodyState bodyState(const Track& track, const VehicleGeometry& geometry, const MotionState& m) {
  BodyState b;
  b.front_track = track.atDistance(m.u_m);
  const TrackPoint rear_track = track.atDistance(m.u_m - geometry.bogie_spacing_m);
  const TrackPoint& ft = b.front_track;
  const Vec f = along(ft.position, ft.d1, ft.d2, m);
  const Vec r = along(rear_track.position, rear_track.d1, rear_track.d2, m);
  b.front = f.v;
  b.rear = r.v;
  b.origin = 0.5 * (f.v + r.v);
  b.origin_v = 0.5 * (f.d + r.d);
  b.origin_a = 0.5 * (f.dd + r.dd);

  // Roll: the mean cant angle under the four wheelsets (or the two pivots).
  Scalar roll{0.0, 0.0, 0.0};
  if (geometry.wheelbase_m > 0.0) {
    const double h = geometry.wheelbase_m / 2.0;
    for (const double u : {m.u_m - h, m.u_m + h, m.u_m - geometry.bogie_spacing_m - h,
                           m.u_m - geometry.bogie_spacing_m + h}) {
      const Track::Roll t = track.rollAtDistance(u);
      roll.v += 0.25 * t.rad;
      roll.d += 0.25 * t.d1 * m.v_m_s;
      roll.dd += 0.25 * (t.d2 * m.v_m_s * m.v_m_s + t.d1 * m.a_m_s2);
    }
  } else {
    for (const TrackPoint* t : {&ft, &rear_track}) {
      roll.v += 0.5 * t->roll_rad;
      roll.d += 0.5 * t->roll_d1 * m.v_m_s;
      roll.dd += 0.5 * (t->roll_d2 * m.v_m_s * m.v_m_s + t->roll_d1 * m.a_m_s2);
    }
  }

  // Axes: x along the chord from the rear to the front pivot; y level (square to the local
  // vertical, the mean of the pivots'), rolled by the cant; z = x × y.
  const Vec up = along(ft.up, ft.up_d1, ft.up_d2, m) +
                 along(rear_track.up, rear_track.up_d1, rear_track.up_d2, m);
  const Vec x = normalized(f - r);
  const Vec y0 = normalized(cross(up, x));
  const Vec z0 = cross(x, y0);
  const Scalar c = cos(roll), s = sin(roll);
  const Vec y = c * y0 + s * z0;
  const Vec z = c * z0 - s * y0;
  b.r_world_body.col(0) = x.v;
  b.r_world_body.col(1) = y.v;
  b.r_world_body.col(2) = z.v;
  // For R = [x y z]: ω = ½ Σ eᵢ × ėᵢ, and its derivative ½ Σ eᵢ × ëᵢ (ėᵢ × ėᵢ = 0).
  const Eigen::Vector3d w = 0.5 * (x.v.cross(x.d) + y.v.cross(y.d) + z.v.cross(z.d));
  const Eigen::Vector3d alpha = 0.5 * (x.v.cross(x.dd) + y.v.cross(y.dd) + z.v.cross(z.dd));
  b.w_body = b.r_world_body.transpose() * w;
  b.alpha_body = b.r_world_body.transpose() * alpha;

  // Euler angles against the local level at the body: R_local_body = attitude(ψ, θ, φ).
  const auto [ef, nf] = eastNorth(ft);
  const auto [er, nr] = eastNorth(rear_track);
  const Eigen::Vector3d u_b = up.v.normalized();
  const Eigen::Vector3d e_b = (ef + er - (ef + er).dot(u_b) * u_b).normalized();
  const Eigen::Vector3d n_b = u_b.cross(e_b);
  b.yaw_rad = std::atan2(x.v.dot(n_b), x.v.dot(e_b));
  b.pitch_rad = std::asin(std::clamp(x.v.dot(u_b), -1.0, 1.0));
  b.roll_rad = roll.v;
  // (φ̇, θ̇, ψ̇) from the body rate: ω_body = (φ̇ + ψ̇ sθ, −θ̇ cφ + ψ̇ cθ sφ, θ̇ sφ + ψ̇ cθ cφ).
  const double sf = std::sin(b.roll_rad), cf = std::cos(b.roll_rad);
  const double yaw_rate = (b.w_body.y() * sf + b.w_body.z() * cf) / std::cos(b.pitch_rad);
  b.euler_rate = {b.w_body.x() - yaw_rate * std::sin(b.pitch_rad),
                  b.w_body.z() * sf - b.w_body.y() * cf, yaw_rate};
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
