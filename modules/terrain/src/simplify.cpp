// Terrain simplification to a vertical error bound: a greedy-insertion TIN (Garland & Heckbert,
// "Fast polygonal approximation of terrains and height fields", 1995) on CGAL's Delaunay
// triangulation in plan (Projection_traits_xy_3). CGAL supplies the triangulation; the
// refinement loop around it is ours because CGAL 5.5 has no height-field simplifier with a
// vertical bound (sensors-reference.md §8: its edge-collapse envelope bounds 3D distance).
// CGAL stays inside this file.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <vector>

#include "trainsim/core/cancel.hpp"
#include "trainsim/terrain/terrain.hpp"

#include "skirt.hpp"

namespace trainsim::terrain {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Projection_traits_xy_3<Kernel>;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Traits>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Traits, Tds>;

struct Worst {
  double error = 0.0;
  std::uint32_t at = 0;
};

// The largest vertical distance between the grid and the plane of triangle (a, b, c), grid
// index i = r·n + c, over the grid points inside or on the triangle.
Worst scanTriangle(const TerrainTile& t, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const auto n = static_cast<std::uint32_t>(t.n);
  const std::array<std::uint32_t, 3> v = {a, b, c};
  long long x[3], y[3];
  double z[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = v[k] % n;
    y[k] = v[k] / n;
    z[k] = t.heights[v[k]];
  }
  const long long area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  Worst worst;
  if (area == 0)
    return worst;
  const long long x0 = std::min({x[0], x[1], x[2]}), x1 = std::max({x[0], x[1], x[2]});
  const long long y0 = std::min({y[0], y[1], y[2]}), y1 = std::max({y[0], y[1], y[2]});
  for (long long py = y0; py <= y1; ++py)
    for (long long px = x0; px <= x1; ++px) {
      // Integer barycentric weights: exact inside/outside decisions.
      const long long w0 = (x[1] - px) * (y[2] - py) - (x[2] - px) * (y[1] - py);
      const long long w1 = (x[2] - px) * (y[0] - py) - (x[0] - px) * (y[2] - py);
      const long long w2 = area - w0 - w1;
      if (area > 0 ? (w0 < 0 || w1 < 0 || w2 < 0) : (w0 > 0 || w1 > 0 || w2 > 0))
        continue;
      const double plane = (static_cast<double>(w0) * z[0] + static_cast<double>(w1) * z[1] +
                            static_cast<double>(w2) * z[2]) /
                           static_cast<double>(area);
      const auto i = static_cast<std::uint32_t>(py * n + px);
      const double e = std::abs(t.heights[i] - plane);
      if (e > worst.error)
        worst = {e, i};
    }
  return worst;
}

}  // namespace

SimplifiedMesh simplifiedTerrainMesh(const TerrainTile& tile, const Eigen::Vector3d& origin,
                                     scene::MaterialId material, double tolerance_m) {
  const auto n = static_cast<std::uint32_t>(tile.n);
  Delaunay tin;
  std::vector<char> inserted(static_cast<std::size_t>(n) * n, 0);
  const auto insert = [&](std::uint32_t i) {
    if (inserted[i])
      return;
    inserted[i] = 1;
    const auto v = tin.insert(Kernel::Point_3(i % n, i / n, tile.heights[i] - tile.z0));
    v->info() = i;
  };
  // Every border vertex: the border stays the full grid's, so tiles meet without cracks.
  for (std::uint32_t k = 0; k < n; ++k) {
    insert(k);
    insert((n - 1) * n + k);
    insert(k * n);
    insert(k * n + n - 1);
  }
  // Every bore vertex and its neighbours: the faces left out are then exactly the cells that
  // touch the bore, as in the full mesh, and no kept face spans the opening.
  for (std::uint32_t r = 0; r < n; ++r)
    for (std::uint32_t c = 0; c < n; ++c)
      if (tile.bore[r * n + c])
        for (std::uint32_t rr = r > 0 ? r - 1 : 0; rr <= std::min(r + 1, n - 1); ++rr)
          for (std::uint32_t cc = c > 0 ? c - 1 : 0; cc <= std::min(c + 1, n - 1); ++cc)
            insert(rr * n + cc);
  // Refine in passes: each triangle still off by more than the tolerance gets its worst grid
  // point; triangles already within it are remembered by their corners and not scanned again.
  struct Key {
    std::array<std::uint32_t, 3> v;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return (static_cast<std::size_t>(k.v[0]) * 0x9E3779B97F4A7C15ull) ^
             (static_cast<std::size_t>(k.v[1]) * 0xC2B2AE3D27D4EB4Full) ^ k.v[2];
    }
  };
  std::unordered_map<Key, Worst, Hash> known;
  const auto key = [](Delaunay::Face_handle f) {
    Key k{{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()}};
    std::sort(k.v.begin(), k.v.end());
    return k;
  };
  double max_error = 0.0;
  for (;;) {
    throwIfCancelled();
    std::vector<std::uint32_t> worst_points;
    max_error = 0.0;
    std::unordered_map<Key, Worst, Hash> next;
    for (auto f = tin.finite_faces_begin(); f != tin.finite_faces_end(); ++f) {
      const Key k = key(f);
      const auto it = known.find(k);
      const Worst w = it != known.end() ? it->second : scanTriangle(tile, k.v[0], k.v[1], k.v[2]);
      next.emplace(k, w);
      max_error = std::max(max_error, w.error);
      if (w.error > tolerance_m)
        worst_points.push_back(w.at);
    }
    known = std::move(next);
    if (worst_points.empty())
      break;
    std::sort(worst_points.begin(), worst_points.end());
    for (const std::uint32_t i : worst_points)
      insert(i);
  }
  SimplifiedMesh out;
  out.max_error_m = max_error;
  scene::Mesh& mesh = out.mesh;
  std::unordered_map<std::uint32_t, std::uint32_t> index;
  // Vertices in grid order, so the mesh is the same bytes however CGAL stored them.
  std::vector<std::uint32_t> order;
  for (auto v = tin.finite_vertices_begin(); v != tin.finite_vertices_end(); ++v)
    order.push_back(v->info());
  std::sort(order.begin(), order.end());
  for (const std::uint32_t i : order) {
    index[i] = mesh.addVertex(
        Eigen::Vector3f(static_cast<float>(tile.origin.x() + (i % n) * tile.spacing_m - origin.x()),
                        static_cast<float>(tile.origin.y() + (i / n) * tile.spacing_m - origin.y()),
                        static_cast<float>(tile.heights[i] - origin.z())));
  }
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (auto f = tin.finite_faces_begin(); f != tin.finite_faces_end(); ++f) {
    if (tile.bore[f->vertex(0)->info()] || tile.bore[f->vertex(1)->info()] ||
        tile.bore[f->vertex(2)->info()])
      continue;
    std::array<std::uint32_t, 3> t = {index[f->vertex(0)->info()], index[f->vertex(1)->info()],
                                      index[f->vertex(2)->info()]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // keeps the winding
    faces.push_back(t);
  }
  std::sort(faces.begin(), faces.end());
  mesh.beginPart(scene::cls::kTerrain, material);
  for (const auto& t : faces)
    mesh.addTriangle(t[0], t[1], t[2]);
  // Skirts under the edges a single kept face has inside the tile: the cut's border. Mesh
  // vertex m is grid point order[m].
  const std::vector<std::uint32_t>& grid_of = order;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& t : faces)
    for (int k = 0; k < 3; ++k)
      ++edges[std::minmax(t[k], t[(k + 1) % 3])];
  const auto on_border = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint32_t ga = grid_of[a], gb = grid_of[b];
    return (ga % n == gb % n && (ga % n == 0 || ga % n == n - 1)) ||
           (ga / n == gb / n && (ga / n == 0 || ga / n == n - 1));
  };
  for (const auto& [e, count] : edges)
    if (count == 1 && !on_border(e.first, e.second))
      detail::addSkirt(mesh, e.first, e.second, tile.skirt[grid_of[e.first]],
                       tile.skirt[grid_of[e.second]]);
  return out;
}

}  // namespace trainsim::terrain
