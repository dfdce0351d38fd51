#pragma once

#include <cstddef>
#include <vector>

namespace trainsim::track {

/// One element of a vertical profile over horizontal chainage s. The pitch θ (angle of the
/// track to the horizontal, positive climbing) follows a circle in the vertical plane:
/// sin θ is linear in s with slope `curvature_1_m` (1/R_v; positive = sag, concave up; zero =
/// constant grade). On a circle dθ/du = curvature_1_m, where u is the distance along the
/// track in 3D, so a train at speed v pitches at exactly v/R_v.
struct VerticalElement {
  double length_m = 0.0;  ///< horizontal length
  double sin_pitch_start = 0.0;
  double curvature_1_m = 0.0;  ///< dθ/du = d(sin θ)/ds
};

/// Height, pitch and along-track distance at one chainage.
struct VerticalState {
  double z_m = 0.0;
  double pitch_rad = 0.0;      ///< θ, positive climbing in the direction of increasing s
  double curvature_1_m = 0.0;  ///< dθ/du
  double distance_m = 0.0;     ///< u: distance along the track in 3D from s = 0
};

/// A vertical point of intersection: grades meet at (chainage, height), rounded by a vertical
/// circle of radius `radius_m` (ignored at the first and last point).
struct Pvi {
  double chainage_m = 0.0;
  double z_m = 0.0;
  double radius_m = 0.0;
};

/// Grades joined by circular vertical curves, in closed form both ways: height, pitch and 3D
/// distance from chainage, and chainage from 3D distance. Chainage is measured horizontally
/// (railway practice); the train's motion is planned in 3D distance u, and ds/du = cos θ.
class VerticalProfile {
 public:
  /// A level profile at height z0 over [0, length].
  VerticalProfile(double length_m = 0.0, double z0_m = 0.0);
  /// Elements laid end to end from chainage 0 at height z0; sin θ is continuous.
  VerticalProfile(double z0_m, std::vector<VerticalElement> elements);

  /// Grades through the PVIs (sorted by chainage, the first at 0), joined by vertical curves.
  /// Where two curves would overlap, their radii are reduced until they fit, and each such
  /// change is returned in `reduced` as (PVI index, radius used).
  static VerticalProfile fromPvis(const std::vector<Pvi>& pvis,
                                  std::vector<std::pair<std::size_t, double>>* reduced = nullptr);

  double length() const { return s_start_.back(); }
  double distanceLength() const { return u_start_.back(); }
  const std::vector<VerticalElement>& elements() const { return elements_; }
  double elementStart(std::size_t i) const { return s_start_[i]; }

  /// State at chainage s; before 0 and after the end the first and last elements extend.
  VerticalState at(double s) const;
  /// Chainage at 3D distance u (inverse of at(s).distance_m), closed form.
  double chainageAt(double u) const;

 private:
  std::size_t indexAtChainage(double s) const;
  std::vector<VerticalElement> elements_;
  std::vector<double> s_start_;
  std::vector<double> u_start_;
  std::vector<double> z_start_;
};

/// Shape of a cant ramp.
enum class RampShape { kLinear, kBloss };

/// One element of a cant profile: applied cant D (signed, m: positive when the left rail is the
/// higher one, i.e. banked for a right-hand curve) ramps from `cant_start_m` to `cant_end_m`.
struct CantElement {
  double length_m = 0.0;
  double cant_start_m = 0.0;
  double cant_end_m = 0.0;
  RampShape shape = RampShape::kLinear;
};

/// Cant and its chainage derivatives at one point.
struct CantState {
  double cant_m = 0.0;
  double rate_m_per_m = 0.0;  ///< dD/ds
  double rate2_1_m = 0.0;     ///< d²D/ds²
};

/// The applied-cant profile along horizontal chainage; constant or ramped (linear or Bloss).
class CantProfile {
 public:
  CantProfile() = default;
  explicit CantProfile(std::vector<CantElement> elements);
  double length() const { return s_start_.empty() ? 0.0 : s_start_.back(); }
  const std::vector<CantElement>& elements() const { return elements_; }
  double elementStart(std::size_t i) const { return s_start_[i]; }
  /// Cant at chainage s; zero outside the profile.
  CantState at(double s) const;

 private:
  std::vector<CantElement> elements_;
  std::vector<double> s_start_;
};

}  // namespace trainsim::track
