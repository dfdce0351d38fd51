#include "camera_sensor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "camera_config.hpp"
#include "class_counts.hpp"
#include "trainsim/camera/exposure.hpp"
#include "trainsim/camera/lens.hpp"
#include "trainsim/camera/renderer.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/scene/atmosphere.hpp"
#include "trainsim/scene/mesh.hpp"
#include "trainsim/scene/semantics.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/instance_table.hpp"
#include "trainsim/sim/sensor_params.hpp"
#include "trainsim/sim/sensor_registry.hpp"
#include "trainsim/terrain/daylight.hpp"

namespace trainsim::sim {
namespace {

static_assert(std::endian::native == std::endian::little,
              "PFM depth is written little-endian by copying memory as is");

// One frame's images, rendered in render(); the instance ids wait for commit().
struct CameraFrame {
  camera::CameraImages images;
  std::string rgb_png, depth_png, depth_pfm, semantic_png, preview_png;  // made in render()
};

class CameraSensor final : public SensorOf<CameraFrame> {
 public:
  CameraSensor(const SensorSetup& setup, const CameraConfig& c)
      : trajectory_(setup.context.trajectory),
        scene_(setup.context.scene),
        instances_(setup.context.instances),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        index_(setup.index),
        cameras_(setup.count),
        T_body_cam0_(setup.context.T_body_cam0),
        config_(c),
        anchor_(setup.context.anchor),
        noise_(setup.context.scenario.seed(), name_ + ".noise"),
        intrinsics_(intrinsics(c)),
        lens_(c.distortion.none() ? nullptr
                                  : std::make_unique<camera::LensRemap>(intrinsics_, c.distortion)),
        lighting_(lighting(c)),
        // Relative to the presets' sunny-16 exposure: 1/100 s, ISO 100, f/16.
        exposure_(c.shutter_s / 0.01 * c.iso / 100.0 * std::pow(16.0 / c.f_number, 2),
                  c.read_noise_dn, c.shot_noise_dn),
        // At night a tunnel is lit as the open line is (the lamps, a faint sky): no shade.
        daylight_(c.daytime == Daytime::kNight ? nullptr : tunnelDaylight(setup)),
        renderer_(rendererOptions(c, lens_ ? lens_->render() : intrinsics_, daylight_)) {
    if (scene_ == nullptr || instances_ == nullptr)
      throw RuntimeError(
          fmt::format("{}: a camera needs the scene (the run did not make it)", setup.path));
    T_body_cam_ = bodyFromCamera(c.basics.mount.mount());
    // What its settings do that may not be meant is said by createSensors (cameraWarnings).
    const camera::Intrinsics& render = renderer_.options().intrinsics;
    reach_m_ = c.far_m * render.farthestRay();
    // The train's own body (train.body) is in the picture of a camera outside it (one looking
    // back along the roof, or down at it), as the box that stops the LiDARs' rays: unlabelled,
    // no instance. A camera inside the box is behind the windscreen and sees out.
    const TrainConfig train = trainSection().read(setup.context.scenario.json());
    if (train.body.enabled) {
      // The box is in the pivots' midpoint's axes, the trajectory's pose the reported point's.
      const Eigen::AlignedBox3d box = train.body.box().translate(-train.reference_point);
      if (!box.contains(T_body_cam_.translation())) {
        auto mesh = std::make_shared<scene::Mesh>();
        mesh->beginPart(scene::cls::kUnlabelled, scene::mat::kPaintedMetal);
        scene::addBox(*mesh, box.min().cast<float>(), box.max().cast<float>());
        body_ = std::move(mesh);
      }
    }
    // Tunnels: the night's lamps and faint light, the day's sky seen through the portals.
    CameraConfig at_night = c;
    at_night.daytime = Daytime::kNight;
    tunnel_lighting_ = lighting(at_night);
    tunnel_lighting_.sky_zenith = lighting_.sky_zenith;
    tunnel_lighting_.sky_horizon = lighting_.sky_horizon;
    // The fog's colour is that of fog lit as under the noon preset (applyFog).
    CameraConfig at_noon = c;
    at_noon.daytime = Daytime::kNoon;
    noon_sky_light_ = skywardLight(lighting(at_noon));
    noon_horizon_ = horizonLuminance(lighting(at_noon));
    if (setup.context.route != nullptr)
      for (const track::Block& block : setup.context.route->blocks)
        if (block.type == track::BlockType::kTunnel)
          tunnels_.push_back(block);
    camera_ahead_of_front_m_ = c.basics.mount.position_m.x() + train.reference_point.x() -
                               0.5 * train.vehicle.bogie_spacing_m;
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return kCameraKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override {
    std::vector<std::string> files = sensorFiles(kReadingsCsv, name_);
    if (config_.rgb)
      files.push_back(io::DatasetLayout::imageFolder(index_) + "/");
    if (config_.depth || config_.depth_float)
      files.push_back(io::DatasetLayout::depthFolder(index_) + "/");
    if (config_.semantic)
      files.push_back(io::DatasetLayout::semanticFolder(index_) + "/");
    if (config_.semantic_preview)
      files.push_back(io::DatasetLayout::semanticPreviewFolder(index_) + "/");
    if (config_.instance)
      files.push_back(io::DatasetLayout::instanceFolder(index_) + "/");
    return files;
  }

  // P_{index + 2} (image_{index + 2}) projects points in camera 0's frame (Tr's and poses.txt's)
  // into this camera's image. P0–P3 are always written, as KITTI's readers expect all four:
  // camera 0 also writes P0 and P1, and P3 when it is the only camera.
  std::vector<std::string> calibration() const override {
    const Eigen::Isometry3d T_cam_cam0 = T_body_cam_.inverse() * T_body_cam0_;
    const Eigen::Matrix<double, 3, 4> P = intrinsics_.matrix() * T_cam_cam0.matrix().topRows<3>();
    const auto line = [&](int n) { return kittiCalibLine(fmt::format("P{}", n), P); };
    std::vector<std::string> lines;
    if (index_ == 0) {
      lines.push_back(line(0));
      lines.push_back(line(1));
    }
    lines.push_back(line(index_ + 2));
    if (index_ == 0 && cameras_ == 1)
      lines.push_back(line(3));
    if (lens_) {  // after P and Tr (generate's order): OpenCV's distortion of image_{index + 2}
      const camera::Distortion& d = config_.distortion;
      lines.push_back(fmt::format("D{}: {:.12e} {:.12e} {:.12e} {:.12e} {:.12e}", index_ + 2, d.k1,
                                  d.k2, d.p1, d.p2, d.k3));
    }
    return lines;
  }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    writer_ = &writer;
    csv_ = &writer.appendFile(writer.layout().inSequence(outputs().front()));
    class_pixels_.restore(state);
    if (state.is_null())
      csv_->write("frame,t_ns,objects,triangles\n");
  }

  // Not null even before a frame: a resumed run must not write the CSV header again.
  nlohmann::json state() const override { return class_pixels_.state(); }
  // The pixels per class of the run's semantic images (when the camera makes them): what
  // classes.yaml's content is taken from when there is no LiDAR.
  nlohmann::json summary() const override { return class_pixels_.summary(); }

 private:
  // `k`: the pinhole to render with (larger than the image with a lens, see LensRemap).
  static camera::RendererOptions rendererOptions(
      const CameraConfig& c, const camera::Intrinsics& k,
      const std::shared_ptr<const terrain::TunnelDaylight>& daylight) {
    camera::RendererOptions o;
    if (daylight) {
      o.daylight = [daylight](std::span<const Eigen::Vector3d> points, std::span<float> shares) {
        daylight->shares(points, shares);
      };
      o.shade_meets = [daylight](const scene::Box3d& box) { return daylight->meets(box); };
    }
    o.intrinsics = k;
    o.near_m = c.near_m;
    o.far_m = c.far_m;
    o.fxaa = c.fxaa;
    // Fog needs each pixel's range, so a foggy colour image needs the depth pass too.
    const bool ids = c.semantic || c.semantic_preview || c.instance;
    o.passes = {c.rgb, c.depth || c.depth_float || (c.rgb && c.fog_visibility_m > 0.0), ids, ids};
    return o;
  }

  // The luminance of a lighting's sky at the horizon, in linear light.
  static double horizonLuminance(const camera::Lighting& l) {
    return 0.2126 * camera::Srgb::toLinear(l.sky_horizon[0]) +
           0.7152 * camera::Srgb::toLinear(l.sky_horizon[1]) +
           0.0722 * camera::Srgb::toLinear(l.sky_horizon[2]);
  }

  // Fog (Beer–Lambert, Koschmieder's extinction β = 3.912 / V at the train) in a layer whose
  // extinction falls as e^(−h/H) at a height h above the camera (H: fog_height_m) and stays β
  // below it. A ray rising at elevation e (sine s) crosses, to range L, the optical depth
  // β L (1 − e^(−a)) / a with a = L s / H (β L level or falling); to the sky, β H / s, and all
  // the fog there is below the horizon. The pixel's light fades to the fog's as e^(−depth).
  // The fog is lit as the scene is: its colour, light grey under the noon preset's sun and sky,
  // scales in linear light with the light a surface facing the sky gets (ambient plus the
  // sun's diffuse share), so a tunnel's fog is as dim as its walls; and with the sky's
  // horizon, which a fog can outshine no more than it does at noon (at night, the ambient
  // share would make it several times brighter than the night sky it stands in).
  // `up`: the local vertical in the camera's axes.
  void applyFog(camera::CameraImages& img, const camera::Lighting& lighting,
                const Eigen::Vector3d& up) const {
    const double beta = scene::fogExtinction(config_.fog_visibility_m), H = config_.fog_height_m;
    const camera::Intrinsics& k = renderer_.options().intrinsics;
    const double lit = std::min(skywardLight(lighting) / noon_sky_light_,
                                horizonLuminance(lighting) / noon_horizon_);
    // Koschmieder's blend of the object's light and the fog's, in linear light.
    constexpr std::uint8_t kFog[3] = {200, 204, 208};
    const double fog[3] = {lit * camera::Srgb::toLinear(kFog[0]),
                           lit * camera::Srgb::toLinear(kFog[1]),
                           lit * camera::Srgb::toLinear(kFog[2])};
    for (int v = 0; v < img.height; ++v)
      for (int u = 0; u < img.width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * img.width + u;
        const double z = img.depth[i];
        const double x = (u - k.cx) / k.fx, y = (v - k.cy) / k.fy;
        const double norm = std::sqrt(1.0 + x * x + y * y);
        const double s = (x * up.x() + y * up.y() + up.z()) / norm;  // sine of the elevation
        const double depth =
            z > 0.0 ? scene::fogDepth(beta, H, z * norm, s) : scene::fogDepthToSky(beta, H, s);
        const double keep = std::exp(-depth);
        for (int ch = 0; ch < 3; ++ch) {
          std::uint8_t& c = img.rgb[3 * i + ch];
          c = camera::Srgb::fromLinear(keep * camera::Srgb::toLinear(c) + (1.0 - keep) * fog[ch]);
        }
      }
  }

  // Exposure and sensor noise on the colour image of sample k, in linear light (camera::Exposure):
  // the render's light scaled by the exposure (t · ISO / N², relative to sunny 16), then Gaussian
  // noise of variance read² + shot² · value / 255 from the counter-based stream (pixel, sample),
  // clipped at white and encoded back to sRGB.
  void develop(camera::CameraImages& img, std::int64_t k) const {
    if (exposure_.identity())
      return;
    std::array<double, 4> z{};
    for (std::size_t i = 0; i < img.rgb.size(); ++i) {
      if (exposure_.noisy() && i % 4 == 0)
        z = noise_.normal4(i / 4, static_cast<std::uint64_t>(k));
      img.rgb[i] = exposure_(img.rgb[i], z[i % 4]);
    }
  }

  CameraFrame read(std::int64_t k) const override {
    const Eigen::Isometry3d pose = trajectory_.sample(k).pose();
    const Eigen::Isometry3d T = pose * T_body_cam_;
    // The far plane is a depth: towards the picture's corners it lies farther than far_m.
    scene::SceneWindow window = scene_->window(T.translation(), reach_m_);
    if (body_) {
      // One tile of its own, under an index no scene tile has.
      auto tile = std::make_shared<scene::Tile>();
      tile->index = {std::numeric_limits<std::int32_t>::min(),
                     std::numeric_limits<std::int32_t>::min()};
      tile->origin = pose.translation();
      tile->objects.push_back(
          scene::Object::place(body_, pose.translation(), pose.linear().cast<float>(), 0));
      tile->updateBounds();
      window.tiles.push_back(std::move(tile));
    }
    CameraFrame out;
    // Each surface lit as much by the day as reaches it (a tunnel's bore is in the shade), the
    // fog as it is where the camera is.
    out.images = renderer_.render(window, T, lighting_, daylight_ ? &tunnel_lighting_ : nullptr);
    if (config_.rgb && config_.fog_visibility_m > 0.0)
      applyFog(out.images, lightingAt(trajectory_.sample(k).chainage_m),
               T.linear().transpose() * anchor_.rotationAnchorFromLocalEnu(T.translation()).col(2));
    if (lens_)
      out.images = lens_->apply(out.images);
    camera::CameraImages& img = out.images;
    if (config_.rgb) {
      develop(img, k);
      out.rgb_png = io::encodePngRgb8(img.width, img.height, img.rgb);
    }
    if (config_.depth) {
      std::vector<std::uint16_t> depth(img.depth.size());
      for (std::size_t i = 0; i < depth.size(); ++i) {
        const double z = img.depth[i];
        depth[i] = z > 0.0 && z <= config_.depth_max_m
                       ? static_cast<std::uint16_t>(std::min(65535L, std::lround(z * 256.0)))
                       : 0;
      }
      out.depth_png =
          io::encodePngGray16(img.width, img.height, depth, io::PngContent::kMeasurement);
    }
    if (config_.depth_float) {
      // PFM: a text header, then rows bottom to top of little-endian float32 (scale < 0).
      std::string& pfm = out.depth_pfm;
      pfm = fmt::format("Pf\n{} {}\n-1.0\n", img.width, img.height);
      const std::size_t header = pfm.size(), row = 4 * static_cast<std::size_t>(img.width);
      pfm.resize(header + row * img.height);
      for (int v = 0; v < img.height; ++v)
        std::memcpy(pfm.data() + header + row * (img.height - 1 - v),
                    img.depth.data() + static_cast<std::size_t>(v) * img.width, row);
    }
    if (config_.semantic)
      out.semantic_png =
          io::encodePngGray8(img.width, img.height, img.semantic, io::PngContent::kLabels);
    if (config_.semantic_preview) {
      std::vector<std::uint8_t> rgb(3 * img.semantic.size());
      for (std::size_t i = 0; i < img.semantic.size(); ++i) {
        const scene::Rgb c = scene::semanticClass(img.semantic[i]).colour;
        std::copy(c.begin(), c.end(), rgb.begin() + static_cast<std::ptrdiff_t>(3 * i));
      }
      out.preview_png = io::encodePngRgb8(img.width, img.height, rgb);
    }
    return out;
  }

  void write(std::int64_t k, CameraFrame& f) override {
    const std::int64_t frame = k / (period_ / trajectory_.samplePeriod());
    const io::DatasetLayout& layout = writer_->layout();
    const auto file = [&](const std::string& folder, const char* ext = "png") {
      return layout.inSequence(io::DatasetLayout::frameFile(folder, frame, ext));
    };
    if (config_.rgb)
      writer_->writeFile(file(io::DatasetLayout::imageFolder(index_)), f.rgb_png);
    if (config_.depth)
      writer_->writeFile(file(io::DatasetLayout::depthFolder(index_)), f.depth_png);
    if (config_.depth_float)
      writer_->writeFile(file(io::DatasetLayout::depthFolder(index_), "pfm"), f.depth_pfm);
    if (config_.semantic)
      writer_->writeFile(file(io::DatasetLayout::semanticFolder(index_)), f.semantic_png);
    if (config_.semantic_preview)
      writer_->writeFile(file(io::DatasetLayout::semanticPreviewFolder(index_)), f.preview_png);
    if (config_.instance) {
      // The sequence's ids, numbered as objects first appear in raster order (the LiDARs of
      // the same sample committed theirs before).
      const camera::CameraImages& img = f.images;
      std::vector<std::int32_t> ids(img.instances.size(), -1);
      std::vector<std::uint16_t> pixels(img.object.size());
      for (std::size_t i = 0; i < pixels.size(); ++i) {
        std::int32_t& id = ids[img.object[i]];
        if (id < 0)
          id = instances_->id(img.instances[img.object[i]], img.semantic[i]);
        pixels[i] = static_cast<std::uint16_t>(id);
      }
      writer_->writeFile(
          file(io::DatasetLayout::instanceFolder(index_)),
          io::encodePngGray16(img.width, img.height, pixels, io::PngContent::kLabels));
    }
    for (const std::uint8_t cls : f.images.semantic)
      class_pixels_.add(cls);
    csv_->write(fmt::format("{},{},{},{}\n", frame, k * trajectory_.samplePeriod(),
                            f.images.objects, f.images.triangles));
  }

  // How much daylight reaches each surface, when the route has tunnels (the tubes' sizes are
  // the terrain section's).
  static std::shared_ptr<const terrain::TunnelDaylight> tunnelDaylight(const SensorSetup& setup) {
    if (setup.context.route == nullptr || setup.context.layout == nullptr)
      return nullptr;
    auto d = std::make_shared<const terrain::TunnelDaylight>(
        *setup.context.route, *setup.context.layout,
        terrainSection().read(setup.context.scenario.json()));
    return d->empty() ? nullptr : d;
  }

  // The light where the camera is, for the fog around it (the surfaces are lit by their own
  // share of daylight, TunnelDaylight): in a tunnel, the sun's and the sky's light fade
  // linearly to none 50 m from a portal (a look, not a light-transport model) and the train's
  // headlights are on; outside, the configured lighting as it is.
  camera::Lighting lightingAt(double front_chainage_m) const {
    const double c = front_chainage_m + camera_ahead_of_front_m_;
    double inside = 0.0;  // metres from the nearer portal, 0 outside
    for (const track::Block& b : tunnels_)
      if (c > b.chainage_begin_m && c < b.chainage_end_m)
        inside = std::min(c - b.chainage_begin_m, b.chainage_end_m - c);
    if (inside <= 0.0)
      return lighting_;
    constexpr double kDaylightReach = 50.0;
    const double day = std::max(0.0, 1.0 - inside / kDaylightReach);
    camera::Lighting l = tunnel_lighting_;
    l.sun_intensity = day * lighting_.sun_intensity;
    l.ambient = tunnel_lighting_.ambient + day * (lighting_.ambient - tunnel_lighting_.ambient);
    return l;
  }

  const Trajectory& trajectory_;
  scene::SceneStream* scene_;
  std::shared_ptr<InstanceTable> instances_;
  std::string name_;
  TimeNs period_;
  int index_;
  int cameras_;
  Eigen::Isometry3d T_body_cam0_, T_body_cam_;
  std::shared_ptr<const scene::Mesh> body_;  // the train's body in the reported point's axes
  CameraConfig config_;
  GeodeticAnchor anchor_;  // the local vertical, for the fog's layer
  RandomStream noise_;
  camera::Intrinsics intrinsics_;  // the image's (calib.txt's P)
  double reach_m_ = 0.0;           // the farthest the render can see (its corners' far plane)
  std::unique_ptr<camera::LensRemap> lens_;
  camera::Lighting lighting_, tunnel_lighting_;
  double noon_sky_light_ = 1.0;           // skywardLight() under the noon preset
  double noon_horizon_ = 1.0;             // horizonLuminance() under the noon preset
  std::vector<track::Block> tunnels_;     // the main track's tunnel blocks
  double camera_ahead_of_front_m_ = 0.0;  // the camera's chainage past the front pivot's
  camera::Exposure exposure_;
  std::shared_ptr<const terrain::TunnelDaylight> daylight_;  // null: no tunnel on the route
  camera::Renderer renderer_;
  io::DatasetWriter* writer_ = nullptr;
  io::AppendFile* csv_ = nullptr;
  ClassCounts class_pixels_{"class_pixels", "pixels"};
};

}  // namespace

scenario::Param declareCamera() {
  return cameraBinding().declare(
      "camera",
      "A camera rendered with VTK (offscreen OpenGL; an X server, or Xvfb started for the run): "
      "KITTI image_N/*.png, depth_N/*.png (uint16 m * 256), semantic_N/*.png (class ids) and "
      "instance_N/*.png (the LiDAR labels' instance ids), one file each per frame.");
}

void checkCamera(const scenario::Json& item, const std::string& path,
                 std::vector<scenario::Problem>& problems) {
  cameraBinding().problems(cameraBinding().read(item), path, problems);
}

std::vector<std::string> warnCamera(const scenario::Json& resolved, const scenario::Json& item,
                                    const std::string& path, int index) {
  return cameraWarnings(cameraBinding().read(item), resolved, path, index);
}

std::unique_ptr<Sensor> createCamera(const SensorSetup& setup) {
  return std::make_unique<CameraSensor>(setup, cameraBinding().read(setup.config));
}

Eigen::Isometry3d cameraBodyPose(const scenario::Json& item) {
  return bodyFromCamera(readMount(item));
}

}  // namespace trainsim::sim
