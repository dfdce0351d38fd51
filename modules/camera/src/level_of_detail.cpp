#include "level_of_detail.hpp"

#include <limits>
#include <unordered_map>
#include <vector>

namespace trainsim::camera {

scene::Mesh clustered(const scene::Mesh& mesh, double cell) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (const Eigen::Vector3f& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // Cell coordinates take 21 bits each in the key; a mesh wider than 2²¹ cells stays as it is.
  if (mesh.vertices.empty() || ((hi - lo).cast<double>() / cell).maxCoeff() >= 0x1p21)
    return mesh;
  std::unordered_map<std::uint64_t, std::uint32_t> cells;
  std::vector<std::uint32_t> merged(mesh.vertices.size());
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> count;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d c = ((mesh.vertices[i] - lo).cast<double>() / cell).array().floor();
    const std::uint64_t key = static_cast<std::uint64_t>(c.x()) << 42 |
                              static_cast<std::uint64_t>(c.y()) << 21 |
                              static_cast<std::uint64_t>(c.z());
    const auto [it, added] = cells.emplace(key, static_cast<std::uint32_t>(sum.size()));
    if (added) {
      sum.emplace_back(Eigen::Vector3d::Zero());
      count.push_back(0);
    }
    merged[i] = it->second;
    sum[it->second] += mesh.vertices[i].cast<double>();
    ++count[it->second];
  }
  scene::Mesh out;
  out.vertices.reserve(sum.size());
  for (std::size_t k = 0; k < sum.size(); ++k)
    out.vertices.push_back((sum[k] / count[k]).cast<float>());
  for (const scene::MeshPart& part : mesh.parts) {
    out.beginPart(part.cls, part.material);
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
         ++t) {
      const std::uint32_t a = merged[mesh.triangles[t][0]], b = merged[mesh.triangles[t][1]],
                          c = merged[mesh.triangles[t][2]];
      if (a != b && b != c && a != c)
        out.addTriangle(a, b, c);
    }
  }
  return out;
}

}  // namespace trainsim::camera
