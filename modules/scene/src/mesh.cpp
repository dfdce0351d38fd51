#include "trainsim/scene/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <Eigen/Geometry>

#include "trainsim/core/error.hpp"

namespace trainsim::scene {

double Box3d::planDistance(const Eigen::Vector2d& p) const {
  const double dx = std::max({min.x() - p.x(), 0.0, p.x() - max.x()});
  const double dy = std::max({min.y() - p.y(), 0.0, p.y() - max.y()});
  return std::hypot(dx, dy);
}

void Mesh::beginPart(ClassId cls, MaterialId material) {
  const auto first = static_cast<std::uint32_t>(triangles.size());
  if (!parts.empty() && parts.back().triangle_count == 0)
    parts.pop_back();
  if (!parts.empty() && parts.back().cls == cls && parts.back().material == material)
    return;
  parts.push_back({first, 0, cls, material});
}

void Mesh::addTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (parts.empty())
    throw RuntimeError("Mesh::addTriangle before beginPart");
  triangles.push_back({a, b, c});
  ++parts.back().triangle_count;
}

void Mesh::addQuad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  addTriangle(a, b, c);
  addTriangle(a, c, d);
}

std::size_t Mesh::bytes() const {
  return vertices.capacity() * sizeof(Eigen::Vector3f) +
         triangles.capacity() * sizeof(triangles[0]) + parts.capacity() * sizeof(MeshPart);
}

void addOrientedBox(Mesh& mesh, const Eigen::Vector3f& c, const Eigen::Vector3f& hx,
                    const Eigen::Vector3f& hy, const Eigen::Vector3f& hz) {
  // Four vertices per face so that each face keeps its own flat normal in renderers.
  const Eigen::Vector3f axes[3] = {hx, hy, hz};
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3f& n = axes[axis];
    const Eigen::Vector3f& u = axes[(axis + 1) % 3];
    const Eigen::Vector3f& v = axes[(axis + 2) % 3];
    for (const float sign : {1.0f, -1.0f}) {
      const Eigen::Vector3f f = c + sign * n;
      const Eigen::Vector3f su = sign * u;  // flips the winding on the negative face
      const auto a = mesh.addVertex(f - su - v), b = mesh.addVertex(f + su - v),
                 d = mesh.addVertex(f + su + v), e = mesh.addVertex(f - su + v);
      mesh.addQuad(a, b, d, e);
    }
  }
}

void addBox(Mesh& mesh, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  const Eigen::Vector3f h = 0.5f * (hi - lo);
  addOrientedBox(mesh, 0.5f * (lo + hi), {h.x(), 0, 0}, {0, h.y(), 0}, {0, 0, h.z()});
}

void addCylinder(Mesh& mesh, const Eigen::Vector3f& bottom, const Eigen::Vector3f& top,
                 float r_bottom, float r_top, int sides) {
  const Eigen::Vector3f axis = (top - bottom).normalized();
  const Eigen::Vector3f helper =
      std::abs(axis.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  const Eigen::Vector3f u = axis.cross(helper).normalized();
  const Eigen::Vector3f v = axis.cross(u);
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int k = 0; k < sides; ++k) {
    const float a =
        2.0f * std::numbers::pi_v<float> * static_cast<float>(k) / static_cast<float>(sides);
    const Eigen::Vector3f dir = std::cos(a) * u + std::sin(a) * v;
    mesh.addVertex(bottom + r_bottom * dir);
    mesh.addVertex(top + r_top * dir);
  }
  const auto n = static_cast<std::uint32_t>(sides);
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t k1 = (k + 1) % n;
    mesh.addQuad(base + 2 * k, base + 2 * k1, base + 2 * k1 + 1, base + 2 * k + 1);
  }
  const auto cb = mesh.addVertex(bottom), ct = mesh.addVertex(top);
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t k1 = (k + 1) % n;
    mesh.addTriangle(cb, base + 2 * k1, base + 2 * k);
    if (r_top > 0.0f)
      mesh.addTriangle(ct, base + 2 * k + 1, base + 2 * k1 + 1);
  }
}

namespace {

struct Icosphere {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

Icosphere makeIcosphere(int subdivisions) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  Icosphere s;
  for (const auto& v :
       {Eigen::Vector3f(-1, t, 0), Eigen::Vector3f(1, t, 0), Eigen::Vector3f(-1, -t, 0),
        Eigen::Vector3f(1, -t, 0), Eigen::Vector3f(0, -1, t), Eigen::Vector3f(0, 1, t),
        Eigen::Vector3f(0, -1, -t), Eigen::Vector3f(0, 1, -t), Eigen::Vector3f(t, 0, -1),
        Eigen::Vector3f(t, 0, 1), Eigen::Vector3f(-t, 0, -1), Eigen::Vector3f(-t, 0, 1)})
    s.vertices.push_back(v.normalized());
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto [it, fresh] = mid.try_emplace({key.first, key.second}, 0);
      if (fresh) {
        s.vertices.push_back((s.vertices[a] + s.vertices[b]).normalized());
        it->second = static_cast<std::uint32_t>(s.vertices.size() - 1);
      }
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& [a, b, c] : s.triangles) {
      const auto ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    s.triangles = std::move(next);
  }
  return s;
}

const Icosphere& icosphere(int subdivisions) {
  static const Icosphere spheres[4] = {makeIcosphere(0), makeIcosphere(1), makeIcosphere(2),
                                       makeIcosphere(3)};
  return spheres[std::clamp(subdivisions, 0, 3)];
}

}  // namespace

std::size_t blobVertexCount(int subdivisions) {
  return icosphere(subdivisions).vertices.size();
}

void addBlob(Mesh& mesh, const Eigen::Vector3f& centre, const Eigen::Vector3f& radii,
             int subdivisions, std::span<const float> jitter) {
  const Icosphere& s = icosphere(subdivisions);
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const float scale = 1.0f + (i < jitter.size() ? jitter[i] : 0.0f);
    mesh.addVertex(centre + scale * radii.cwiseProduct(s.vertices[i]));
  }
  for (const auto& [a, b, c] : s.triangles)
    mesh.addTriangle(base + a, base + b, base + c);
}

}  // namespace trainsim::scene
