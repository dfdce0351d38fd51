// The `layout` and `train` sections: declarations bound to track::LayoutParams and TrainConfig.

#include "trainsim/sim/config.hpp"

namespace trainsim::sim {
namespace {

using scenario::Binding;
using scenario::Problem;
namespace units = scenario::units;
constexpr scenario::Unit kM = units::si("m");

const Binding<track::LayoutParams>& auxiliaryBinding() {
  // The auxiliary-track fields are flat in LayoutParams and nested in JSON: this binding reads
  // the `auxiliary` object into the same struct.
  static const Binding<track::LayoutParams> binding = [] {
    using L = track::LayoutParams;
    Binding<L> b;
    b.number("probability", &L::aux_probability, units::kNone,
             "Probability per eligible straight stretch")
        .range(0, 1);
    b.number("parallel_min_m", &L::aux_parallel_min_m, kM, "Shortest parallel part").range(10, 1e5);
    b.number("parallel_max_m", &L::aux_parallel_max_m, kM, "Longest parallel part").range(10, 1e5);
    b.number("turnout_probability", &L::turnout_probability, units::kNone,
             "Probability that an end joins the next track through a turnout (else it is a "
             "dead end)")
        .range(0, 1);
    b.choice("turnout", &L::turnout, "Turnout type (radius-crossing ratio)");
    b.number("dead_end_length_m", &L::dead_end_length_m, kM, "Length of a dead-end straight")
        .range(1, 1e4);
    b.choice("side", &L::side, "Side of the main track (right: beyond the double track)");
    b.notAbove(&L::aux_parallel_min_m, &L::aux_parallel_max_m);
    return b;
  }();
  return binding;
}

const Binding<track::TrainDynamics>& dynamicsBinding() {
  static const Binding<track::TrainDynamics> binding = [] {
    using D = track::TrainDynamics;
    Binding<D> b;
    b.boolean("enabled", &D::enabled, "Limit acceleration by traction, Davis resistance and grade");
    b.number("mass_kg", &D::mass_kg, units::si("kg"), "Train mass").range(1e3, 1e8);
    b.number("rotating_mass_factor", &D::rotating_mass_factor, units::kNone, "1 + rho").range(1, 2);
    b.number("davis_a_n", &D::davis_a_n, units::si("N"), "Davis A").range(0, 1e7);
    b.number("davis_b_n_s_m", &D::davis_b_n_s_m, units::si("N s/m"), "Davis B").range(0, 1e7);
    b.number("davis_c_n_s2_m2", &D::davis_c_n_s2_m2, units::si("N s^2/m^2"), "Davis C")
        .range(0, 1e7);
    b.number("max_traction_n", &D::max_traction_n, units::si("N"), "Starting tractive effort")
        .range(0, 1e8);
    b.number("max_power_w", &D::max_power_w, units::si("W"), "Traction power (effort falls as P/v)")
        .range(1, 1e9);
    return b;
  }();
  return binding;
}

const Binding<BodyConfig>& bodyBinding() {
  static const Binding<BodyConfig> binding = [] {
    Binding<BodyConfig> b;
    b.boolean("enabled", &BodyConfig::enabled,
              "LiDAR rays that meet the body end there without a return (a LiDAR on the roof "
              "does not see the track through the train); cameras outside it see it as an "
              "unlabelled box (a camera inside it is behind the windscreen)");
    b.number("front_x_m", &BodyConfig::front_x_m, kM,
             "Front edge of the roof, forward of the origin midway between the bogie pivots "
             "(the nose below it is not modelled)")
        .range(-100, 100);
    b.number("length_m", &BodyConfig::length_m, kM,
             "Length of the lead vehicle, rigid with its sensors (the cars behind it follow the "
             "curves and are not modelled)")
        .range(1, 100);
    b.number("width_m", &BodyConfig::width_m, kM, "Width of the body").range(0.5, 5);
    b.number("roof_m", &BodyConfig::roof_m, kM, "Height of the roof above top of rail")
        .range(0.5, 6);
    return b;
  }();
  return binding;
}

const Binding<Eigen::Vector3d>& referencePointBinding() {
  static const Binding<Eigen::Vector3d> binding = [] {
    Binding<Eigen::Vector3d> b(Eigen::Vector3d::Zero());
    bindBodyPosition(b, [](Eigen::Vector3d& v) -> Eigen::Vector3d& { return v; });
    return b;
  }();
  return binding;
}

}  // namespace

const scenario::Section<track::LayoutParams>& layoutSection() {
  static const scenario::Section<track::LayoutParams> section = [] {
    using L = track::LayoutParams;
    scenario::Section<L> s{"layout", "Tracks beside the main track (railroad.json).", {}, {}};
    Binding<L>& b = s.binding;
    b.boolean("double_track", &L::double_track, "Second track on the right of the main track");
    b.number("track_centre_distance_m", &L::track_centre_distance_m, kM,
             "Distance between neighbouring track centres")
        .range(3.0, 10.0);
    b.number("polyline_spacing_m", &L::polyline_spacing_m, kM,
             "Largest spacing of railroad.json polylines")
        .range(0.1, 100);
    b.object(
        "auxiliary", [](L& l) -> L& { return l; }, auxiliaryBinding(),
        "Auxiliary tracks: entering, parallel and outgoing parts.");
    return s;
  }();
  return section;
}

const scenario::Section<TrainConfig>& trainSection() {
  static const scenario::Section<TrainConfig> section = [] {
    scenario::Section<TrainConfig> s{
        "train", "The train: longitudinal limits, dynamics and the body on its bogies.", {}, {}};
    Binding<TrainConfig>& b = s.binding;
    const auto limit = [](double track::MotionLimits::*m) {
      return scenario::nested(&TrainConfig::limits, m);
    };
    b.number("max_accel_m_s2", limit(&track::MotionLimits::accel_m_s2), units::si("m/s^2"),
             "Largest acceleration")
        .range(0.01, 5);
    b.number("max_brake_m_s2", limit(&track::MotionLimits::brake_m_s2), units::si("m/s^2"),
             "Service braking deceleration")
        .range(0.01, 5);
    b.number("max_jerk_m_s3", limit(&track::MotionLimits::jerk_m_s3), units::si("m/s^3"),
             "Largest longitudinal jerk")
        .range(0.01, 10);
    b.number("length_m", limit(&track::MotionLimits::train_length_m), kM,
             "Train length: restrictions hold until the rear clears them")
        .range(1, 2000);
    b.number("bogie_spacing_m",
             scenario::nested(&TrainConfig::vehicle, &track::VehicleGeometry::bogie_spacing_m), kM,
             "Distance between the front car's bogie pivots")
        .range(1, 40);
    b.number("bogie_wheelbase_m",
             scenario::nested(&TrainConfig::vehicle, &track::VehicleGeometry::wheelbase_m), kM,
             "Distance between a bogie's two wheelsets: the body rolls with the mean cant under "
             "its four wheelsets, so a linear cant ramp turns the roll rate over this length "
             "instead of in a step; 0: the cant at the pivots")
        .range(0, 6);
    b.object("reference_point", &TrainConfig::reference_point, referencePointBinding(),
             "Body point whose pose is reported (body axes x fwd, y left, z up; origin midway "
             "between the bogie pivots at top of rail)");
    b.object("dynamics", &TrainConfig::dynamics, dynamicsBinding(),
             "Optional traction and running resistance limiting acceleration.");
    b.object("body", &TrainConfig::body, bodyBinding(),
             "The lead vehicle's body as a box in body axes (origin midway between the bogie "
             "pivots at top of rail): what it hides from the LiDARs and cameras on it.");
    b.boolean("stop_for_obstacles", &TrainConfig::stop_for_obstacles,
              "An obstacle in the train's way (objects.obstacles, on any layout track, whose "
              "footprint reaches within half the body's width of the main track's centre) ends "
              "the run: the "
              "train brakes to a stop obstacle_margin_m short of the first one, and the route "
              "beyond it is not driven (trajectory.standstill_end_s records it standing there); "
              "false: the train runs through obstacles");
    b.number("obstacle_margin_m", &TrainConfig::obstacle_margin_m, kM,
             "How far short of an obstacle in its way the train's front stops")
        .range(0, 10000);
    b.check([](const TrainConfig& c, const scenario::FieldPaths<TrainConfig>& at,
               std::vector<Problem>& out) {
      if (c.vehicle.bogie_spacing_m > c.limits.train_length_m)
        out.push_back(
            {at(c.vehicle.bogie_spacing_m), "must not exceed " + at(c.limits.train_length_m)});
      if (c.vehicle.wheelbase_m >= c.vehicle.bogie_spacing_m)
        out.push_back(
            {at(c.vehicle.wheelbase_m), "must be below " + at(c.vehicle.bogie_spacing_m)});
    });
    return s;
  }();
  return section;
}

}  // namespace trainsim::sim
