#include "cwe/workpiece/dexel/tri_dexel.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_reduce.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

int cross_b(int axis) { return (axis + 1) % 3; }
int cross_c(int axis) { return (axis + 2) % 3; }

}  // namespace

TriDexel TriDexel::empty_grid(const Aabb& box, double spacing) {
  if (box.is_empty() || !(box.size().minCoeff() > 0.0) || !box.size().allFinite()) {
    throw InputError("stock box: expected min < max on every axis");
  }
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(fmt::format("dexel spacing {} mm: expected a positive length", spacing));
  }
  TriDexel d;
  d.spacing_ = spacing;
  // Whole cells: grow the box symmetrically to multiples of the spacing.
  std::array<int, 3> cells{};
  Vec3 size;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil(box.size()[a] / spacing - tol::kRelative);
    if (n > 1e7) {
      throw InputError(
          fmt::format("dexel spacing {} mm is too fine for a {} mm stock", spacing, box.size()[a]));
    }
    cells[static_cast<std::size_t>(a)] = static_cast<int>(n);
    size[a] = n * spacing;
  }
  d.domain_ = {box.center() - size / 2.0, box.center() + size / 2.0};
  for (int a = 0; a < 3; ++a) {
    const int nb = cells[static_cast<std::size_t>(cross_b(a))];
    const int nc = cells[static_cast<std::size_t>(cross_c(a))];
    if (static_cast<double>(nb) * nc > static_cast<double>(kMaxRaysPerFamily)) {
      throw InputError(fmt::format("dexel spacing {} mm would need {} rays in one family", spacing,
                                   static_cast<double>(nb) * nc));
    }
    d.grid_[static_cast<std::size_t>(a)] = {nb, nc};
    d.rays_[static_cast<std::size_t>(a)].resize(static_cast<std::size_t>(nb) * nc);
  }
  return d;
}

TriDexel TriDexel::from_box(const Aabb& box, double spacing) {
  TriDexel d = empty_grid(box, spacing);
  for (int a = 0; a < 3; ++a) {
    // Every ray of the block carries the stock between the box's faces along it.
    const auto lo = static_cast<float>(box.min[a] - d.domain_.min[a]);
    const auto hi = static_cast<float>(box.max[a] - d.domain_.min[a]);
    auto& family = d.rays_[static_cast<std::size_t>(a)];
    std::fill(family.begin(), family.end(), DexelRay(lo, hi));
  }
  return d;
}

std::size_t TriDexel::ray_count() const {
  return rays_[0].size() + rays_[1].size() + rays_[2].size();
}

std::size_t TriDexel::index(int axis, int i, int j) const {
  const auto& g = grid_[static_cast<std::size_t>(axis)];
  CWE_ASSERT(i >= 0 && i < g[0] && j >= 0 && j < g[1], "dexel ray index out of range");
  return static_cast<std::size_t>(j) * static_cast<std::size_t>(g[0]) + static_cast<std::size_t>(i);
}

Ray TriDexel::ray(int axis, int i, int j) const {
  Vec3 origin = domain_.min;
  origin[cross_b(axis)] += (i + 0.5) * spacing_;
  origin[cross_c(axis)] += (j + 0.5) * spacing_;
  return {origin, Vec3::Unit(axis)};
}

const DexelRay& TriDexel::at(int axis, int i, int j) const {
  return rays_[static_cast<std::size_t>(axis)][index(axis, i, j)];
}

std::array<int, 2> TriDexel::index_range(int axis, int cross, double lo, double hi) const {
  const int n = grid_[static_cast<std::size_t>(axis)][cross == cross_b(axis) ? 0 : 1];
  // Ray k sits at min + (k + ½)s: it lies within [lo, hi] for k in [lo'/s - ½, hi'/s - ½].
  const double first = std::ceil((lo - domain_.min[cross]) / spacing_ - 0.5);
  const double last = std::floor((hi - domain_.min[cross]) / spacing_ - 0.5);
  return {static_cast<int>(std::clamp(first, 0.0, static_cast<double>(n))),
          static_cast<int>(std::clamp(last, -1.0, static_cast<double>(n - 1)))};
}

TriDexel::Removal TriDexel::remove(const Aabb& bounds, const ChordFunction& chord) {
  Removal removal;
  if (bounds.is_empty() || !bounds.intersects(domain_)) return removal;
  double length = 0.0;
  for (int a = 0; a < 3; ++a) {
    const int b = cross_b(a), c = cross_c(a);
    const auto is = index_range(a, b, bounds.min[b], bounds.max[b]);
    const auto js = index_range(a, c, bounds.min[c], bounds.max[c]);
    if (is[0] > is[1] || js[0] > js[1]) continue;
    // The solid's extent along the rays, in ray coordinates: a ray with no material inside it
    // cannot change (touching at an end removes only a point of a closed interval).
    const double low = bounds.min[a] - domain_.min[a], high = bounds.max[a] - domain_.min[a];
    auto& family = rays_[static_cast<std::size_t>(a)];
    // Tiles of kTile × kTile rays are the unit of parallel work. Each ray belongs to one tile
    // and its result does not depend on any other ray, so the outcome is the same for any
    // number of threads or order of tiles.
    struct Tally {
      std::size_t changed = 0;
      double length = 0.0;      // material length removed
      std::ptrdiff_t heap = 0;  // change of heap bytes
    };
    const Tally tally = tbb::parallel_reduce(
        tbb::blocked_range2d<int>(js[0], js[1] + 1, kTile, is[0], is[1] + 1, kTile), Tally{},
        [&](const tbb::blocked_range2d<int>& tile, Tally sum) {
          for (int j = tile.rows().begin(); j < tile.rows().end(); ++j) {
            for (int i = tile.cols().begin(); i < tile.cols().end(); ++i) {
              DexelRay& material = family[index(a, i, j)];
              if (!material.overlaps(low, high)) continue;
              const Interval cut = chord(ray(a, i, j));
              if (cut.is_empty()) continue;
              const auto before = static_cast<std::ptrdiff_t>(material.heap_bytes());
              const double removed = material.subtract(cut.lo, cut.hi);
              if (removed == 0.0) continue;
              ++sum.changed;
              sum.length += removed;
              sum.heap += static_cast<std::ptrdiff_t>(material.heap_bytes()) - before;
            }
          }
          return sum;
        },
        [](Tally x, const Tally& y) {
          x.changed += y.changed;
          x.length += y.length;
          x.heap += y.heap;
          return x;
        });
    removal.rays += tally.changed;
    length += tally.length;
    heap_bytes_ = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(heap_bytes_) + tally.heap);
  }
  peak_heap_bytes_ = std::max(peak_heap_bytes_, heap_bytes_);
  removal.volume = length * spacing_ * spacing_ / 3.0;
  return removal;
}

double TriDexel::Volume::spread() const {
  return *std::max_element(by_family.begin(), by_family.end()) -
         *std::min_element(by_family.begin(), by_family.end());
}

TriDexel::Volume TriDexel::volume() const {
  Volume v;
  for (std::size_t a = 0; a < 3; ++a) {
    double length = 0.0;
    for (const DexelRay& r : rays_[a]) length += r.length();
    v.by_family[a] = length * spacing_ * spacing_;
  }
  return v;
}

bool TriDexel::contains(const Vec3& p) const {
  int votes = 0;
  for (int a = 0; a < 3; ++a) {
    const auto& g = grid_[static_cast<std::size_t>(a)];
    const int b = cross_b(a), c = cross_c(a);
    const auto i = static_cast<int>(std::floor((p[b] - domain_.min[b]) / spacing_));
    const auto j = static_cast<int>(std::floor((p[c] - domain_.min[c]) / spacing_));
    if (i < 0 || j < 0 || i >= g[0] || j >= g[1]) continue;
    if (at(a, i, j).contains(p[a] - domain_.min[a])) ++votes;
  }
  return votes >= 2;
}

TriDexel::Memory TriDexel::memory() const {
  Memory m;
  for (const auto& family : rays_) m.ray_bytes += family.size() * sizeof(DexelRay);
  m.heap_bytes = heap_bytes_;
  m.peak_heap_bytes = peak_heap_bytes_;
  return m;
}

std::size_t TriDexel::count_heap_bytes() const {
  std::size_t bytes = 0;
  for (const auto& family : rays_) {
    for (const DexelRay& r : family) bytes += r.heap_bytes();
  }
  return bytes;
}

}  // namespace cwe
