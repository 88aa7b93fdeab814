// Stock from a closed triangle mesh by exact scan conversion (see TriDexel::from_mesh).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace cwe {
namespace {

__extension__ using Wide = __int128;  // products of two snapped coordinates (< 2^90)

// Snapped coordinates are multiples of s_a / 2^kSnapBits (the cell side along each axis a) from
// the domain's lower corner; ray k of a family then sits exactly at k·2^kSnapBits +
// 2^(kSnapBits-1). Inside-triangle tests and interpolation are affine, so scaling the axes apart
// changes nothing.
constexpr int kSnapBits = 20;
constexpr std::int64_t kCell = std::int64_t{1} << kSnapBits;

struct Snapped {
  std::int64_t b, c;
};

int sign(Wide v) { return (v > 0) - (v < 0); }

// Orientation of ray centre o against the directed edge p → q in the (b, c) plane, for o
// perturbed to o + (ε, ε²): positive when o lies to the left. Never zero for a proper edge, and
// exactly opposite for q → p, so the triangles sharing an edge or vertex never both claim o and
// never both miss it.
int side(const Snapped& p, const Snapped& q, const Snapped& o) {
  const Wide db = q.b - p.b, dc = q.c - p.c;
  const Wide e = db * (o.c - p.c) - dc * (o.b - p.b);
  if (e != 0) return sign(e);
  if (dc != 0) return -sign(dc);
  return sign(db);
}

Wide edge_function(const Snapped& p, const Snapped& q, const Snapped& o) {
  return Wide{q.b - p.b} * (o.c - p.c) - Wide{q.c - p.c} * (o.b - p.b);
}

std::int64_t floor_div(std::int64_t x, std::int64_t d) {
  return x >= 0 ? x / d : -((-x + d - 1) / d);
}

struct Crossing {
  std::uint64_t ray;  // index in the family
  double t;           // ray coordinate, mm from the domain's lower face
  int delta;          // +1 entering the solid (normal against the ray), -1 leaving
  bool operator<(const Crossing& o) const {
    if (ray != o.ray) return ray < o.ray;
    if (t != o.t) return t < o.t;
    return delta > o.delta;  // at equal t enter first: solids touching at a face merge
  }
};

}  // namespace

TriDexel TriDexel::from_mesh(const TriangleMesh& mesh, double spacing, const std::string& source) {
  require_closed_stock(mesh, source);
  for (const auto& t : mesh.triangles) {
    for (const int v : t) {
      CWE_ASSERT(v >= 0 && static_cast<std::size_t>(v) < mesh.vertices.size(),
                 "triangle vertex index out of range");
    }
  }
  TriDexel d = empty_grid(mesh.bounds(), spacing);

  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const auto& g = d.grid_[static_cast<std::size_t>(a)];
    std::vector<Snapped> snapped(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      const Vec3 rel = (mesh.vertices[v] - d.domain_.min).cwiseQuotient(d.spacing_) *
                       static_cast<double>(kCell);
      snapped[v] = {std::llround(rel[b]), std::llround(rel[c])};
    }
    tbb::enumerable_thread_specific<std::vector<Crossing>> found;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 1024),
        [&](const tbb::blocked_range<std::size_t>& range) {
          auto& out = found.local();
          for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const auto& tri = mesh.triangles[k];
            const std::array<Snapped, 3> p{snapped[static_cast<std::size_t>(tri[0])],
                                           snapped[static_cast<std::size_t>(tri[1])],
                                           snapped[static_cast<std::size_t>(tri[2])]};
            const Wide w = edge_function(p[0], p[1], p[2]);
            if (w == 0) continue;  // parallel to the rays (in the snapped projection)
            const int orientation = sign(w);
            std::array<double, 3> h{};
            for (std::size_t m = 0; m < 3; ++m) {
              h[m] = mesh.vertices[static_cast<std::size_t>(tri[m])][a] - d.domain_.min[a];
            }
            const auto [hmin, hmax] = std::minmax({h[0], h[1], h[2]});
            // Ray centres k·cell + cell/2 inside the triangle's (b, c) bounds.
            const auto first = [](std::int64_t lo) {
              return floor_div(lo - kCell / 2 + kCell - 1, kCell);
            };
            const auto last = [](std::int64_t hi) { return floor_div(hi - kCell / 2, kCell); };
            const std::int64_t i0 =
                std::max<std::int64_t>(0, first(std::min({p[0].b, p[1].b, p[2].b})));
            const std::int64_t i1 =
                std::min<std::int64_t>(g[0] - 1, last(std::max({p[0].b, p[1].b, p[2].b})));
            const std::int64_t j0 =
                std::max<std::int64_t>(0, first(std::min({p[0].c, p[1].c, p[2].c})));
            const std::int64_t j1 =
                std::min<std::int64_t>(g[1] - 1, last(std::max({p[0].c, p[1].c, p[2].c})));
            for (std::int64_t j = j0; j <= j1; ++j) {
              for (std::int64_t i = i0; i <= i1; ++i) {
                const Snapped o{i * kCell + kCell / 2, j * kCell + kCell / 2};
                if (side(p[0], p[1], o) != orientation || side(p[1], p[2], o) != orientation ||
                    side(p[2], p[0], o) != orientation) {
                  continue;
                }
                // Barycentric weights of the (unperturbed) centre give the crossing's height.
                const auto w1 = static_cast<double>(edge_function(p[2], p[0], o));
                const auto w2 = static_cast<double>(edge_function(p[0], p[1], o));
                const double t = std::clamp(
                    h[0] + (w1 * (h[1] - h[0]) + w2 * (h[2] - h[0])) / static_cast<double>(w), hmin,
                    hmax);
                // Positive orientation: the normal points along +a, the ray leaves the solid.
                out.push_back({static_cast<std::uint64_t>(j) * static_cast<std::uint64_t>(g[0]) +
                                   static_cast<std::uint64_t>(i),
                               t, -orientation});
              }
            }
          }
        });
    std::vector<Crossing> crossings;
    for (auto& part : found) crossings.insert(crossings.end(), part.begin(), part.end());
    tbb::parallel_sort(crossings.begin(), crossings.end());

    auto& family = d.rays_[static_cast<std::size_t>(a)];
    std::vector<Interval> material;
    for (std::size_t k = 0; k < crossings.size();) {
      const std::uint64_t ray = crossings[k].ray;
      material.clear();
      int winding = 0;
      double start = 0.0;
      for (; k < crossings.size() && crossings[k].ray == ray; ++k) {
        const int before = winding;
        winding += crossings[k].delta;
        if (before == 0 && winding != 0) start = crossings[k].t;
        if (before != 0 && winding == 0) material.push_back({start, crossings[k].t});
      }
      // Exact counting on a closed mesh: every ray leaves the solid as often as it enters.
      CWE_ASSERT(winding == 0, "scan conversion of a closed mesh left a ray inside the solid");
      family[ray].assign(material);
    }
  }
  d.heap_bytes_ = d.count_heap_bytes();
  d.peak_heap_bytes_ = d.heap_bytes_;
  return d;
}

}  // namespace cwe
