#include "trainsim/camera/lens.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "trainsim/core/error.hpp"

namespace trainsim::camera {

Eigen::Vector2d Distortion::apply(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y(), r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

struct LensRemap::Maps {
  cv::Mat x, y;  // CV_32FC1, output size: where each output pixel's ray meets the render
};

namespace {

// The pinhole points (x, y) = (X/Z, Y/Z) imaged at `pixels` (CV_64FC2, a column), by inverting
// the distortion (OpenCV's iteration, run until it settles); `worst` is how far, in pixels, the
// distortion of those points lands from the pixels it should give back.
cv::Mat undistorted(const cv::Mat& pixels, const Intrinsics& k, const Distortion& d,
                    double& worst) {
  const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const cv::Matx<double, 1, 5> D(d.k1, d.k2, d.p1, d.p2, d.k3);
  cv::Mat xy;
  cv::undistortPoints(
      pixels, xy, K, D, cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-14));
  worst = 0.0;
  for (int i = 0; i < xy.rows; ++i) {
    const cv::Vec2d p = xy.at<cv::Vec2d>(i);
    const Eigen::Vector2d back = d.apply({p[0], p[1]});
    const cv::Vec2d q = pixels.at<cv::Vec2d>(i);
    worst =
        std::max(worst, std::hypot(k.fx * back.x() + k.cx - q[0], k.fy * back.y() + k.cy - q[1]));
  }
  return xy;
}

std::string foldMessage(double worst) {
  return fmt::format(
      "the lens distortion cannot be inverted over the image (off by {:.3g} px at worst): the "
      "coefficients fold the image over itself within its field of view",
      worst);
}

constexpr std::string_view kPrefix = "camera: ";  // of ConfigError's messages here

Intrinsics renderFor(const Intrinsics& output, const cv::Mat& xy);

// Every output pixel's pinhole point, row by row; throws if the inversion fails anywhere.
cv::Mat undistortedGrid(const Intrinsics& k, const Distortion& d) {
  cv::Mat pixels(k.width * k.height, 1, CV_64FC2);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u)
      pixels.at<cv::Vec2d>(v * k.width + u) = {static_cast<double>(u), static_cast<double>(v)};
  double worst = 0.0;
  cv::Mat xy = undistorted(pixels, k, d, worst);
  if (!(worst < 1e-3))
    throw ConfigError("camera: " + foldMessage(worst));
  return xy;
}

}  // namespace

std::string lensProblem(const Intrinsics& k, const Distortion& d) {
  // The image's rim: the distortion's polynomial first stops being invertible at the largest
  // radius it has to cover, and the rim holds every pixel's largest radius in its direction.
  cv::Mat rim(0, 1, CV_64FC2);
  for (int u = 0; u < k.width; ++u)
    for (const int v : {0, k.height - 1})
      rim.push_back(cv::Vec2d(u, v));
  for (int v = 1; v + 1 < k.height; ++v)
    for (const int u : {0, k.width - 1})
      rim.push_back(cv::Vec2d(u, v));
  double worst = 0.0;
  undistorted(rim, k, d, worst);
  if (!(worst < 1e-3))
    return foldMessage(worst);
  // The pinhole render it needs, from every pixel (as LensRemap makes it): generate refuses one
  // too large, so validate does too.
  try {
    renderFor(k, undistortedGrid(k, d));
  } catch (const ConfigError& e) {
    const std::string_view why = e.what();
    return std::string(why.starts_with(kPrefix) ? why.substr(kPrefix.size()) : why);
  }
  return {};
}

LensRemap::LensRemap(const Intrinsics& output, const Distortion& distortion)
    : output_(output), maps_(std::make_unique<Maps>()) {
  const cv::Mat xy = undistortedGrid(output, distortion);
  render_ = renderFor(output, xy);
  const auto at = [&](int u, int v) { return xy.at<cv::Vec2d>(v * output.width + u); };
  maps_->x.create(output.height, output.width, CV_32FC1);
  maps_->y.create(output.height, output.width, CV_32FC1);
  for (int v = 0; v < output.height; ++v)
    for (int u = 0; u < output.width; ++u) {
      const cv::Vec2d p = at(u, v);
      maps_->x.at<float>(v, u) = static_cast<float>(render_.fx * p[0] + render_.cx);
      maps_->y.at<float>(v, u) = static_cast<float>(render_.fy * p[1] + render_.cy);
    }
}

namespace {

// The pinhole camera to render `output`'s rays with, from every output pixel's pinhole point
// `xy` (undistortedGrid); throws if it folds or would be too large.
Intrinsics renderFor(const Intrinsics& output, const cv::Mat& xy) {
  Intrinsics render;
  const auto at = [&](int u, int v) { return xy.at<cv::Vec2d>(v * output.width + u); };
  // The render's focal lengths: at least one render pixel per output pixel everywhere (the
  // smallest step of the pinhole coordinates between neighbouring output pixels).
  double step_x = 1.0 / output.fx, step_y = 1.0 / output.fy;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (int v = 0; v < output.height; ++v)
    for (int u = 0; u < output.width; ++u) {
      const cv::Vec2d p = at(u, v);
      x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]);
      y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
      if (u + 1 < output.width)
        step_x = std::min(step_x, at(u + 1, v)[0] - p[0]);
      if (v + 1 < output.height)
        step_y = std::min(step_y, at(u, v + 1)[1] - p[1]);
    }
  if (!(step_x > 0.0 && step_y > 0.0))
    throw ConfigError(std::string(kPrefix) + "the lens distortion folds the image over itself");
  render.fx = 1.0 / step_x;
  render.fy = 1.0 / step_y;
  // One pixel of margin around the rays' extent, so bilinear lookups stay inside.
  render.cx = 1.0 - x0 * render.fx;
  render.cy = 1.0 - y0 * render.fy;
  // In double: a lens nearly folding asks for more pixels than an int holds.
  const double width = std::ceil((x1 - x0) * render.fx) + 3.0;
  const double height = std::ceil((y1 - y0) * render.fy) + 3.0;
  if (!(width <= 8192.0 && height <= 8192.0))
    throw ConfigError(fmt::format(
        "{}the lens distortion needs a {:.0f} x {:.0f} pinhole render (at most 8192 x 8192): the "
        "field of view is too wide for a pinhole",
        kPrefix, width, height));
  render.width = static_cast<int>(width);
  render.height = static_cast<int>(height);
  return render;
}

}  // namespace

LensRemap::~LensRemap() = default;

namespace {

template <typename T>
void remapInto(const std::vector<T>& in, int channels, int type, const Intrinsics& from,
               const cv::Mat& map_x, const cv::Mat& map_y, int interpolation, std::vector<T>& out) {
  if (in.empty())
    return;
  const cv::Mat src(from.height, from.width, CV_MAKETYPE(type, channels),
                    const_cast<T*>(in.data()));
  out.resize(static_cast<std::size_t>(map_x.rows) * map_x.cols * channels);
  cv::Mat dst(map_x.rows, map_x.cols, CV_MAKETYPE(type, channels), out.data());
  cv::remap(src, dst, map_x, map_y, interpolation, cv::BORDER_CONSTANT);
}

}  // namespace

CameraImages LensRemap::apply(const CameraImages& rendered) const {
  CameraImages out;
  out.width = output_.width;
  out.height = output_.height;
  out.instances = rendered.instances;
  out.triangles = rendered.triangles;
  out.objects = rendered.objects;
  const cv::Mat &mx = maps_->x, &my = maps_->y;
  remapInto(rendered.rgb, 3, CV_8U, render_, mx, my, cv::INTER_LINEAR, out.rgb);
  remapInto(rendered.depth, 1, CV_32F, render_, mx, my, cv::INTER_NEAREST, out.depth);
  remapInto(rendered.semantic, 1, CV_8U, render_, mx, my, cv::INTER_NEAREST, out.semantic);
  remapInto(rendered.object, 1, CV_16U, render_, mx, my, cv::INTER_NEAREST, out.object);
  return out;
}

}  // namespace trainsim::camera
