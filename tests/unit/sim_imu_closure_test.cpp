// Does the IMU's output integrate back to the route? An independent strapdown mechanisation —
// not TrainSim's inertial code: GeographicLib's WGS-84 normal gravity and local frame, the
// standard two-sample coning and sculling corrections — integrates an ideal IMU's output of a
// 10 km default route at 100 Hz from the true initial state, and its position is compared with
// the true sensor position along the whole run (docs/PERFORMANCE.md, "IMU closure").
#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/NormalGravity.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <Eigen/Geometry>

#include "trainsim/core/frames.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {
namespace fs = std::filesystem;

std::vector<std::vector<double>> readRows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ','))
      row.push_back(std::stod(f));
    rows.push_back(std::move(row));
  }
  return rows;
}

Eigen::Matrix3d expSo3(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  return a == 0.0 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(a, phi / a).toRotationMatrix();
}

// Navigation in the Earth-fixed Cartesian frame of the anchor (ENU axes at the anchor):
//   Ċ = C [ω_is]× − [Ω]× C,  v̇ = C f + g(p) − 2 Ω × v,  ṗ = v.
class Strapdown {
 public:
  Strapdown(const GeodeticPoint& anchor, Eigen::Vector3d p, Eigen::Vector3d v, Eigen::Matrix3d c)
      : local_(anchor.latitude_deg, anchor.longitude_deg, anchor.height_m),
        omega_(GeographicLib::Constants::WGS84_omega() *
               Eigen::Vector3d(0.0, std::cos(anchor.latitude_deg * kRadPerDeg),
                               std::sin(anchor.latitude_deg * kRadPerDeg))),
        p_(std::move(p)),
        v_(std::move(v)),
        c_(std::move(c)) {}

  // One period T of increments (Δθ, Δv) resolved in the sensor axes at its start.
  void step(const Eigen::Vector3d& dtheta, const Eigen::Vector3d& dv, double T) {
    const Eigen::Matrix3d earth_half = expSo3(-omega_ * T / 2);
    const Eigen::Vector3d dv_world = earth_half * c_ * dv;
    c_ = expSo3(-omega_ * T) * c_ * expSo3(dtheta);
    // Gravity and Coriolis at the midpoint, with the velocity predicted then corrected.
    Eigen::Vector3d v1 = v_ + dv_world + T * (gravity(p_ + v_ * T / 2) - 2 * omega_.cross(v_));
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d vm = (v_ + v1) / 2;
      v1 = v_ + dv_world + T * (gravity(p_ + vm * T / 2) - 2 * omega_.cross(vm));
    }
    p_ += T * (v_ + v1) / 2;
    v_ = v1;
  }
  // Mean specific force and rate over the period: the two-sample coning and sculling
  // corrections (Savage) turn them into increments.
  void stepMeans(const Eigen::Vector3d& f, const Eigen::Vector3d& w, double T) {
    const Eigen::Vector3d a = w * T, u = f * T;
    Eigen::Vector3d dtheta = a, dv = u + 0.5 * a.cross(u);
    if (has_prev_) {
      dtheta += prev_a_.cross(a) / 12.0;
      dv += (prev_a_.cross(u) + prev_u_.cross(a)) / 12.0;
    }
    prev_a_ = a;
    prev_u_ = u;
    has_prev_ = true;
    step(dtheta, dv, T);
  }
  const Eigen::Vector3d& position() const { return p_; }

 private:
  Eigen::Vector3d gravity(const Eigen::Vector3d& p) {
    double lat = 0, lon = 0, h = 0;
    std::vector<double> m(9);
    local_.Reverse(p.x(), p.y(), p.z(), lat, lon, h, m);
    // Normal gravity is symmetric about the Earth's axis: no east component.
    double gy = 0, gz = 0;
    GeographicLib::NormalGravity::WGS84().Gravity(lat, h, gy, gz);
    const double gx = 0.0;
    return Eigen::Matrix3d(Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.data())) *
           Eigen::Vector3d(gx, gy, gz);
  }

  GeographicLib::LocalCartesian local_;
  Eigen::Vector3d omega_;
  Eigen::Vector3d p_, v_;
  Eigen::Matrix3d c_;
  Eigen::Vector3d prev_a_ = Eigen::Vector3d::Zero(), prev_u_ = Eigen::Vector3d::Zero();
  bool has_prev_ = false;
};

struct Closure {
  double max_m = 0.0;
  double end_m = 0.0;
  double run_m = 0.0;  // distance the train ran
};

class ImuClosure : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scenario::Json input = loadScenario("").json();
    input["route"]["generator"]["length_m"] = 10000;
    const scenario::Json mount = {{"x_m", 8.0},      {"y_m", 0.4},       {"z_m", 3.5},
                                  {"roll_deg", 180}, {"pitch_deg", 0.0}, {"yaw_deg", 90}};
    scenario::Json imus = scenario::Json::array();
    for (const auto& [name, sampling, increments] : {std::tuple{"mean", "interval_mean", false},
                                                     {"inc", "interval_mean", true},
                                                     {"inst", "instantaneous", false}})
      imus.push_back({{"name", name},
                      {"preset", "ideal"},
                      {"sampling", sampling},
                      {"increments", increments},
                      {"mount", mount}});
    input["sensors"] = {{"imus", imus}};
    scenario_ =
        std::make_unique<scenario::Scenario>(scenario::Scenario::resolve(input, scenarioSchema()));
    plan_ = makePlan(*scenario_);
    // One folder per process: ctest runs the tests of this suite in parallel processes.
    out_ = fs::temp_directory_path() / ("trainsim-imu-closure-" + std::to_string(::getpid()));
    fs::remove_all(out_);
    GenerateOptions options;
    options.out = out_;
    generate(*scenario_, options);
  }
  static void TearDownTestSuite() {
    fs::remove_all(out_);
    plan_.reset();
    scenario_.reset();
  }

  // Integrates imu `name` (rows at t_k = k T; row k covers (t_{k-1}, t_k]) and compares with
  // the true sensor position at every row.
  static Closure integrate(const std::string& name, bool increments, bool instantaneous) {
    const auto rows = readRows(out_ / "sequences/00" / (name + ".csv"));
    const TrainTrajectory& traj = plan_->trajectory();
    const Eigen::Vector3d arm(8.0, 0.4, 3.5);
    const Eigen::Matrix3d r_body_sensor = attitude(90 * kRadPerDeg, 0, 180 * kRadPerDeg);
    const auto truth = [&](TimeNs t) {
      const TrajectorySample s = traj.at(t);
      const Eigen::Matrix3d r = s.q_world_body.toRotationMatrix();
      return std::tuple{Eigen::Vector3d(s.p_world + r * arm),
                        Eigen::Vector3d(s.v_world + r * s.w_body.cross(arm)),
                        Eigen::Matrix3d(r * r_body_sensor)};
    };
    const auto [p0, v0, c0] = truth(0);
    Strapdown nav(geodeticOriginSection().read(scenario_->json()), p0, v0, c0);
    Closure out;
    const double T = 0.01;
    const auto vec = [](const std::vector<double>& r, int i) {
      return Eigen::Vector3d(r[i], r[i + 1], r[i + 2]);
    };
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const std::vector<double>& r = rows[k];
      if (increments)
        nav.step(vec(r, 13), vec(r, 10), T);
      else if (instantaneous)  // trapezoid of the two instants
        nav.stepMeans((vec(rows[k - 1], 1) + vec(r, 1)) / 2, (vec(rows[k - 1], 4) + vec(r, 4)) / 2,
                      T);
      else
        nav.stepMeans(vec(r, 1), vec(r, 4), T);
      const double e = (nav.position() - std::get<0>(truth(static_cast<TimeNs>(r[0])))).norm();
      out.max_m = std::max(out.max_m, e);
      out.end_m = e;
    }
    out.run_m = traj.at(traj.endTime()).distance_m - traj.at(0).distance_m;
    return out;
  }

  static std::unique_ptr<scenario::Scenario> scenario_;
  static std::unique_ptr<Plan> plan_;
  static fs::path out_;
};
std::unique_ptr<scenario::Scenario> ImuClosure::scenario_;
std::unique_ptr<Plan> ImuClosure::plan_;
fs::path ImuClosure::out_;

TEST_F(ImuClosure, IntervalMeansCloseWithinOneCentimetreOverTenKilometres) {
  const Closure c = integrate("mean", false, false);
  RecordProperty("max_error_m", std::to_string(c.max_m));
  std::cout << "interval means: max " << c.max_m << " m, end " << c.end_m << " m over " << c.run_m
            << " m\n";
  EXPECT_GT(c.run_m, 9900.0);
  EXPECT_LE(c.max_m, 0.01);
}

TEST_F(ImuClosure, IncrementsCloseWithinOneCentimetreOverTenKilometres) {
  const Closure c = integrate("inc", true, false);
  std::cout << "increments: max " << c.max_m << " m, end " << c.end_m << " m\n";
  EXPECT_LE(c.max_m, 0.01);
}

// Documented, not a target: instantaneous samples cannot carry the steps of the roll rate at
// the ends of linear cant ramps (docs/PERFORMANCE.md records the figure).
TEST_F(ImuClosure, InstantaneousSamplesAreWorseThanMeans) {
  const Closure inst = integrate("inst", false, true);
  const Closure mean = integrate("mean", false, false);
  std::cout << "instantaneous: max " << inst.max_m << " m, end " << inst.end_m << " m\n";
  EXPECT_GT(inst.max_m, 10 * mean.max_m);
}

}  // namespace
}  // namespace trainsim::sim
