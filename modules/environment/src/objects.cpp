// Trackside objects: the kind registry, their seeded prototypes and the object-position
// generator.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "objects.hpp"
#include "trainsim/core/random.hpp"

namespace trainsim::environment {
namespace {

using scene::Mesh;

std::vector<float> jitter(std::uint64_t seed, std::string_view stream, int variant, std::size_t n,
                          float amount) {
  const RandomStream random(seed, stream);
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = amount * static_cast<float>(
                          2.0 * random.uniform4(static_cast<std::uint64_t>(variant), i)[0] - 1.0);
  return out;
}

// A tree's trunk radius at its foot, in footprint radii: what it stands on (its crown, all of the
// footprint, stood it on the lowest ground under it, sunk up to 2.2 m on the slopes).
constexpr double kTrunkShare = 0.12;

// Trees: odd variants broadleaf (trunk and a lumpy round crown), even ones conifers (trunk and a
// cone); footprint radius 1, height about 4–6.
Mesh tree(std::uint64_t seed, int variant) {
  Mesh m;
  const RandomStream random(seed, "objects/tree-shape");
  const auto u = random.uniform4(static_cast<std::uint64_t>(variant));
  const float height = 4.0f + 2.0f * static_cast<float>(u[0]);
  m.beginPart(scene::cls::kTrunk, scene::mat::kBark);
  scene::addCylinder(m, {0, 0, -0.2f}, {0, 0, 0.45f * height}, static_cast<float>(kTrunkShare),
                     0.08f, 8);
  if (variant % 2 == 1) {
    m.beginPart(scene::cls::kTree, scene::mat::kLeaves);
    const auto j = jitter(seed, "objects/tree-crown", variant, scene::blobVertexCount(2), 0.15f);
    scene::addBlob(m, {0, 0, 0.62f * height}, {0.9f, 0.9f, 0.38f * height}, 2, j);
  } else {
    m.beginPart(scene::cls::kTree, scene::mat::kNeedles);
    scene::addCylinder(m, {0, 0, 0.2f * height}, {0, 0, height}, 1.0f, 0.0f, 10);
  }
  return m;
}

Mesh bush(std::uint64_t seed, int variant) {
  Mesh m;
  m.beginPart(scene::cls::kVegetation, scene::mat::kLeaves);
  const auto j = jitter(seed, "objects/bush", variant, scene::blobVertexCount(1), 0.2f);
  scene::addBlob(m, {0, 0, 0.45f}, {0.9f, 0.9f, 0.6f}, 1, j);
  return m;
}

Mesh rock(std::uint64_t seed, int variant) {
  Mesh m;
  m.beginPart(scene::cls::kRock, scene::mat::kRock);
  const auto j = jitter(seed, "objects/rock", variant, scene::blobVertexCount(1), 0.25f);
  scene::addBlob(m, {0, 0, 0.15f}, {0.85f, 0.75f, 0.55f}, 1, j);
  return m;
}

// A house inside the unit footprint: walls, a gable roof; variants differ in proportions and
// wall material.
Mesh building(std::uint64_t seed, int variant) {
  Mesh m;
  const RandomStream random(seed, "objects/building-shape");
  const auto u = random.uniform4(static_cast<std::uint64_t>(variant));
  const float hx = 0.55f + 0.15f * static_cast<float>(u[0]);
  const float hy = std::sqrt(std::max(0.1f, 0.9f - hx * hx));
  const float wall = 0.45f + 0.35f * static_cast<float>(u[1]);
  const float ridge = wall + 0.25f + 0.2f * static_cast<float>(u[2]);
  m.beginPart(scene::cls::kBuilding, u[3] < 0.5 ? scene::mat::kPlaster : scene::mat::kBrick);
  scene::addBox(m, {-hx, -hy, -0.1f}, {hx, hy, wall});
  // Gable ends.
  for (const float x : {-hx, hx}) {
    const auto a = m.addVertex({x, -hy, wall}), b = m.addVertex({x, hy, wall}),
               c = m.addVertex({x, 0, ridge});
    if (x > 0)
      m.addTriangle(a, b, c);
    else
      m.addTriangle(b, a, c);
  }
  m.beginPart(scene::cls::kBuilding, scene::mat::kRoofTile);
  for (const float side : {-1.0f, 1.0f}) {
    const float eave = side * (hy + 0.08f);
    const auto a = m.addVertex({-hx - 0.08f, eave, wall - 0.05f}),
               b = m.addVertex({hx + 0.08f, eave, wall - 0.05f}),
               c = m.addVertex({hx + 0.08f, 0, ridge}), d = m.addVertex({-hx - 0.08f, 0, ridge});
    if (side > 0)
      m.addQuad(b, a, d, c);
    else
      m.addQuad(a, b, c, d);
  }
  return m;
}

// The registry: name, description, defaults (density per hectare, nearest track centre to the
// footprint's edge), footprint radii, variants, prototype.
const ObjectKind kKinds[] = {
    {"trees", "Trees (broadleaf and conifer)", {12.0, 6.0}, 1.5, 3.5, 8, tree, kTrunkShare},
    {"bushes", "Bushes", {10.0, 6.0}, 0.6, 1.5, 6, bush},
    {"rocks", "Rocks and boulders", {3.0, 6.0}, 0.3, 1.2, 6, rock},
    {"buildings", "Houses and sheds", {0.4, 15.0}, 4.0, 9.0, 6, building},
};

}  // namespace

std::span<const ObjectKind> objectKinds() {
  return kKinds;
}

ObjectParams::ObjectParams() {
  for (const ObjectKind& k : kKinds)
    kinds.push_back(k.defaults);
}

namespace detail {

std::vector<PlacedObject> placeObjects(const Environment& env, scene::TileIndex index,
                                       const terrain::TerrainTile* heights) {
  const ObjectParams& P = env.params().objects;
  const auto kinds = objectKinds();
  const scene::TileGrid grid = env.grid();
  const Eigen::Vector2d lo = grid.corner(index);
  const Eigen::Vector2d hi = lo + Eigen::Vector2d::Constant(grid.size_m);
  // Nothing on a platform or across a fence line, whatever a kind's own distance says.
  const AssetParams& A = env.params().assets;
  double floor_m = A.platform_edge_m + A.platform_width_m + 0.5;
  if (A.fence_probability > 0.0)
    floor_m = std::max(floor_m, A.fence_offset_m + 0.5);
  const auto min_distance = [&](std::size_t k) {
    return std::max(P.kinds[k].min_track_distance_m, floor_m);
  };
  double r_max = 0.0, reach = 0.0;
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    r_max = std::max(r_max, kinds[k].radius_max_m);
    reach = std::max(reach, min_distance(k) + kinds[k].radius_max_m);
  }
  // Candidates in the tile and in a margin wide enough to hold every candidate that could
  // overlap one in the tile: a candidate's fate depends only on candidates within 2·r_max, so
  // the result is the same whichever tile decides it.
  const double margin = 2.0 * r_max + P.cell_m;
  const terrain::TrackDistance distance(env.railway(), lo - Eigen::Vector2d::Constant(margin),
                                        hi + Eigen::Vector2d::Constant(margin), reach);
  const RandomStream random(env.seed(), "objects/candidates");
  const double cell_area_ha = P.cell_m * P.cell_m / 1e4;
  struct Candidate {
    std::size_t kind;
    Eigen::Vector2d p;
    double radius, priority;
    std::int64_t ci, cj;
    bool valid;
  };
  const auto c0 = static_cast<std::int64_t>(std::floor((lo.x() - margin) / P.cell_m));
  const auto c1 = static_cast<std::int64_t>(std::floor((hi.x() + margin) / P.cell_m));
  const auto r0 = static_cast<std::int64_t>(std::floor((lo.y() - margin) / P.cell_m));
  const auto r1 = static_cast<std::int64_t>(std::floor((hi.y() + margin) / P.cell_m));
  const std::int64_t w = c1 - c0 + 1;
  std::vector<int> at(static_cast<std::size_t>(w * (r1 - r0 + 1)), -1);
  std::vector<Candidate> candidates;
  for (std::int64_t cj = r0; cj <= r1; ++cj)
    for (std::int64_t ci = c0; ci <= c1; ++ci) {
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ci)) << 32) |
                                static_cast<std::uint32_t>(cj);
      const auto u = random.uniform4(key, 0);
      // One candidate per cell at most: kind k with probability density_k · cell area.
      double cumulative = 0.0;
      std::size_t kind = kinds.size();
      for (std::size_t k = 0; k < kinds.size(); ++k) {
        cumulative += P.kinds[k].density_per_ha * cell_area_ha;
        if (u[0] < cumulative) {
          kind = k;
          break;
        }
      }
      if (kind == kinds.size())
        continue;
      const auto v = random.uniform4(key, 1);
      Candidate c{
          kind,
          {(static_cast<double>(ci) + u[1]) * P.cell_m,
           (static_cast<double>(cj) + u[2]) * P.cell_m},
          kinds[kind].radius_min_m + v[0] * (kinds[kind].radius_max_m - kinds[kind].radius_min_m),
          u[3],
          ci,
          cj,
          false};
      c.valid = distance(c.p.x(), c.p.y()) >= min_distance(kind) + c.radius;
      at[static_cast<std::size_t>((cj - r0) * w + (ci - c0))] = static_cast<int>(candidates.size());
      candidates.push_back(c);
    }
  // A valid candidate stands if no overlapping valid candidate has a higher priority (ties by
  // cell): the local-maximum rule, which needs no order of placement.
  const auto cells = static_cast<std::int64_t>(std::ceil(2.0 * r_max / P.cell_m)) + 1;
  std::vector<PlacedObject> placed;
  std::uint32_t serial = 0;
  for (const Candidate& c : candidates) {
    if (!c.valid || c.p.x() < lo.x() || c.p.x() >= hi.x() || c.p.y() < lo.y() || c.p.y() >= hi.y())
      continue;
    bool stands = true;
    for (std::int64_t dj = -cells; dj <= cells && stands; ++dj)
      for (std::int64_t di = -cells; di <= cells && stands; ++di) {
        if (di == 0 && dj == 0)
          continue;
        const std::int64_t ci = c.ci + di, cj = c.cj + dj;
        if (ci < c0 || ci > c1 || cj < r0 || cj > r1)
          continue;
        const int o = at[static_cast<std::size_t>((cj - r0) * w + (ci - c0))];
        if (o < 0)
          continue;
        const Candidate& other = candidates[static_cast<std::size_t>(o)];
        if (!other.valid || (other.p - c.p).norm() >= other.radius + c.radius)
          continue;
        if (other.priority > c.priority ||
            (other.priority == c.priority && std::pair(other.cj, other.ci) > std::pair(c.cj, c.ci)))
          stands = false;
      }
    if (!stands)
      continue;
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.ci)) << 32) |
                              static_cast<std::uint32_t>(c.cj);
    const auto v = random.uniform4(key, 1);
    PlacedObject o;
    o.kind = c.kind;
    o.variant = static_cast<int>(v[1] * kinds[c.kind].variants) % kinds[c.kind].variants;
    o.radius_m = c.radius;
    o.yaw_rad = 2.0 * std::numbers::pi * v[2];
    double z = 0.0;
    if (heights) {
      // Lowest ground under the foot's centre and four rim points (ObjectKind::foot_share of the
      // footprint), so nothing floats: from the tile's height grid, or beyond it from the grid
      // cell there as the next tile has it (clamped to the grid's edge, an object by a tile's
      // border stood on the wrong ground, up to 0.37 m above the lowest).
      z = std::numeric_limits<double>::infinity();
      const double extent = (heights->n - 1) * heights->spacing_m;
      const double foot = c.radius * kinds[c.kind].foot_share;
      for (const auto& d :
           {Eigen::Vector2d(0, 0), Eigen::Vector2d(foot, 0), Eigen::Vector2d(-foot, 0),
            Eigen::Vector2d(0, foot), Eigen::Vector2d(0, -foot)}) {
        const Eigen::Vector2d point = c.p + d, in = point - heights->origin;
        const bool inside = in.minCoeff() >= 0.0 && in.maxCoeff() <= extent;
        z = std::min(z, inside ? terrainHeight(*heights, point)
                               : env.terrain().gridHeightAt(point.x(), point.y()));
      }
    }
    o.position = {c.p.x(), c.p.y(), z};
    o.instance = scene::objectInstance(index.i, index.j, serial++);
    placed.push_back(o);
  }
  return placed;
}

double terrainHeight(const terrain::TerrainTile& t, const Eigen::Vector2d& p) {
  const double u = std::clamp((p.x() - t.origin.x()) / t.spacing_m, 0.0, t.n - 1.000001);
  const double v = std::clamp((p.y() - t.origin.y()) / t.spacing_m, 0.0, t.n - 1.000001);
  const int c = static_cast<int>(u), r = static_cast<int>(v);
  const double fx = u - c, fy = v - r;
  const double h00 = t.height(c, r), h10 = t.height(c + 1, r), h01 = t.height(c, r + 1),
               h11 = t.height(c + 1, r + 1);
  return (1 - fy) * ((1 - fx) * h00 + fx * h10) + fy * ((1 - fx) * h01 + fx * h11);
}

}  // namespace detail
}  // namespace trainsim::environment
