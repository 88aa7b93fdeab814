#include "cwe/workpiece/dexel/tri_dexel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/core/memory_limit.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

int cross_b(int axis) { return (axis + 1) % 3; }
int cross_c(int axis) { return (axis + 2) % 3; }

// The cells along x, y, z a stock box at `spacing` gets: the fewest whole cells no wider than the
// spacing, one at least (a spacing above the box's size gives one ray per family through its
// middle). Doubles: they are checked against the limits before any cast.
std::array<double, 3> cells_for(const Aabb& box, double spacing) {
  std::array<double, 3> cells{};
  for (int a = 0; a < 3; ++a) {
    cells[static_cast<std::size_t>(a)] =
        std::max(1.0, std::ceil(box.size()[a] / spacing - tol::kRelative));
  }
  return cells;
}

}  // namespace

void TriDexel::check_grid(const Aabb& box, double spacing, const SourceLocation& where) {
  const std::array<double, 3> n = cells_for(box, spacing);
  const double rays = n[0] * n[1] + n[1] * n[2] + n[2] * n[0];
  const Vec3 size = box.size();
  for (int a = 0; a < 3; ++a) {
    const double family =
        n[static_cast<std::size_t>(cross_b(a))] * n[static_cast<std::size_t>(cross_c(a))];
    if (n[static_cast<std::size_t>(a)] > 1e7 || family > static_cast<double>(kMaxRaysPerFamily)) {
      throw InputError(where, fmt::format("{:g} mm is too fine for a {:g} × {:g} × {:g} mm "
                                          "stock: it would need {:.3g} rays",
                                          spacing, size.x(), size.y(), size.z(), rays));
    }
  }
  // Each ray, and each row's tiles their free spans.
  double bytes = rays * static_cast<double>(sizeof(DexelRay));
  for (int a = 0; a < 3; ++a) {
    bytes += static_cast<double>(sizeof(FreeSpan)) * n[static_cast<std::size_t>(cross_c(a))] *
             std::ceil(n[static_cast<std::size_t>(cross_b(a))] / kTile);
  }
  check_memory(bytes,
               fmt::format("{:g} mm: the {:.3g} dexel rays of a {:g} × {:g} × {:g} mm stock",
                           spacing, rays, size.x(), size.y(), size.z()),
               where, "use a coarser resolution");
}

TriDexel TriDexel::empty_grid(const Aabb& box, double spacing, bool filled) {
  if (box.is_empty() || !(box.size().minCoeff() > 0.0) || !box.size().allFinite()) {
    throw InputError("stock box: expected min < max on every axis");
  }
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(fmt::format("dexel spacing {} mm: expected a positive length", spacing));
  }
  // Every bound is checked before anything is allocated.
  check_grid(box, spacing);
  const std::array<double, 3> n = cells_for(box, spacing);
  TriDexel d;
  std::array<int, 3> cells{};
  for (int a = 0; a < 3; ++a) {
    cells[static_cast<std::size_t>(a)] = static_cast<int>(n[static_cast<std::size_t>(a)]);
    d.spacing_[a] = box.size()[a] / n[static_cast<std::size_t>(a)];
    d.inverse_spacing_[a] = 1.0 / d.spacing_[a];
  }
  d.domain_ = box;
  for (int a = 0; a < 3; ++a) {
    d.grid_[static_cast<std::size_t>(a)] = {cells[static_cast<std::size_t>(cross_b(a))],
                                            cells[static_cast<std::size_t>(cross_c(a))]};
  }
  // At the start of a job nothing else runs, and making millions of rays is most of it; most of
  // that is the first write to their pages. The families' room first, its pages faulted in on
  // all threads a huge page at a time (one family, Z on a flat block, holds most of the rays:
  // faulted in by the thread that made it, it kept that thread busy while the other idled); then
  // the three families at once.
  std::array<std::size_t, 3> count{};        // rays of each family
  std::array<std::size_t, 4> first_block{};  // each family's first block, and the end
  for (std::size_t a = 0; a < 3; ++a) {
    count[a] = static_cast<std::size_t>(d.grid_[a][0]) * static_cast<std::size_t>(d.grid_[a][1]);
    d.rays_[a].reserve(count[a]);
    advise_huge_pages(d.rays_[a].data(), count[a] * sizeof(DexelRay));
    first_block[a + 1] =
        first_block[a] + (count[a] * sizeof(DexelRay) + kHugePageBytes - 1) / kHugePageBytes;
  }
  tbb::parallel_for(std::size_t{0}, first_block[3], [&](std::size_t block) {
    std::size_t a = 0;
    while (block >= first_block[a + 1]) ++a;
    const std::size_t from = (block - first_block[a]) * kHugePageBytes;
    populate_pages(reinterpret_cast<const char*>(d.rays_[a].data()) + from,
                   std::min(kHugePageBytes, count[a] * sizeof(DexelRay) - from));
  });
  tbb::parallel_for(0, 3, [&](int a) {
    const auto& g = d.grid_[static_cast<std::size_t>(a)];
    // Filled: every ray of the block carries the stock between the box's faces along it, made
    // as it is allocated (one pass over the rays, not a default one and then a copy).
    const DexelRay ray = filled ? DexelRay(0.0f, static_cast<float>(box.size()[a])) : DexelRay();
    auto& rays = d.rays_[static_cast<std::size_t>(a)];
    rays.assign(count[static_cast<std::size_t>(a)], ray);
    d.free_[static_cast<std::size_t>(a)].assign(
        d.free_row(a, g[1], 0),
        {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()});
  });
  return d;
}

TriDexel TriDexel::from_box(const Aabb& box, double spacing) {
  return empty_grid(box, spacing, true);
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
  const int b = cross_b(axis), c = cross_c(axis);
  return {ray_origin(axis, domain_.min[b] + (i + 0.5) * spacing_[b],
                     domain_.min[c] + (j + 0.5) * spacing_[c]),
          Vec3::Unit(axis)};
}

const DexelRay& TriDexel::at(int axis, int i, int j) const {
  return rays_[static_cast<std::size_t>(axis)][index(axis, i, j)];
}

std::span<const DexelRay> TriDexel::row(int axis, int j) const {
  const auto n = static_cast<std::size_t>(grid_[static_cast<std::size_t>(axis)][0]);
  return {&rays_[static_cast<std::size_t>(axis)][index(axis, 0, j)], n};
}

std::array<int, 2> TriDexel::index_range(int axis, int cross, double lo, double hi) const {
  const int n = grid_[static_cast<std::size_t>(axis)][cross == cross_b(axis) ? 0 : 1];
  // Ray k sits at min + (k + ½)s: it lies within [lo, hi] for k in [lo'/s - ½, hi'/s - ½].
  const double first = std::ceil((lo - domain_.min[cross]) / spacing_[cross] - 0.5);
  const double last = std::floor((hi - domain_.min[cross]) / spacing_[cross] - 0.5);
  return {static_cast<int>(std::clamp(first, 0.0, static_cast<double>(n))),
          static_cast<int>(std::clamp(last, -1.0, static_cast<double>(n - 1)))};
}

TriDexel::Removal TriDexel::remove(const Aabb& bounds, const ChordFunction& chord) {
  return remove(std::vector<Cut>{{bounds, chord, {}, {}}}).front();
}

std::vector<TriDexel::Removal> TriDexel::remove(const std::vector<Cut>& cuts,
                                                RemovalRecord* record) {
  const std::vector<RemovalRecord*> records(cuts.size(), record);
  if (record != nullptr && cuts.empty()) record->clear();
  return remove(cuts, records);
}

std::vector<TriDexel::Removal> TriDexel::remove(const std::vector<Cut>& cuts,
                                                std::span<RemovalRecord* const> records,
                                                Indexing indexing) {
  CWE_ASSERT(records.size() == cuts.size(), "one record (or null) per cut");
  // The records, each once (its cuts follow one another): the first and last cut of each.
  struct Owner {
    RemovalRecord* record;
    std::size_t first, last;
  };
  std::vector<Owner> owners;
  std::vector<std::size_t> owner_of(cuts.size(), 0);  // index in owners, of cuts with a record
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    if (records[k] == nullptr) continue;
    if (owners.empty() || owners.back().record != records[k]) {
      owners.push_back({records[k], k, k});
      records[k]->clear();
    }
    owners.back().last = k;
    owner_of[k] = owners.size() - 1;
  }
  std::vector<Removal> removals(cuts.size());
  std::vector<double> lengths(cuts.size(), 0.0);  // volumes summed over the three families
  // What one tile did for one cut.
  struct Tally {
    std::size_t changed = 0;
    double length = 0.0;      // material length removed
    std::ptrdiff_t heap = 0;  // change of heap bytes
  };
  // Each family's pass: each cut's rays (index ranges) and its extent along them, in ray
  // coordinates (a ray with no material inside it cannot change: touching at an end removes only a
  // point), and the tiles the cuts reach, numbered after the previous family's.
  struct Reach {
    std::array<int, 2> is{0, -1}, js{0, -1};
    double low = 0.0, high = 0.0;
  };
  struct Pass {
    int a = 0;
    std::vector<Reach> reach;
    int ti0 = 0, tj0 = 0, nti = 0, ntj = 0;
    std::size_t first = 0;  // the pass's first tile among all of them
    std::size_t tiles() const {
      return static_cast<std::size_t>(nti) * static_cast<std::size_t>(ntj);
    }
  };
  std::array<Pass, 3> passes;
  std::size_t tile_count = 0;
  for (int a = 0; a < 3; ++a) {
    Pass& pass = passes[static_cast<std::size_t>(a)];
    const int b = cross_b(a), c = cross_c(a);
    pass.a = a;
    pass.first = tile_count;
    pass.reach.resize(cuts.size());
    std::array<int, 2> all_is{std::numeric_limits<int>::max(), -1}, all_js = all_is;
    for (std::size_t k = 0; k < cuts.size(); ++k) {
      const Aabb& box = cuts[k].bounds;
      if (box.is_empty() || !box.intersects(domain_)) continue;
      Reach& r = pass.reach[k];
      r.is = index_range(a, b, box.min[b], box.max[b]);
      r.js = index_range(a, c, box.min[c], box.max[c]);
      if (r.is[0] > r.is[1] || r.js[0] > r.js[1]) continue;
      r.low = box.min[a] - domain_.min[a];
      r.high = box.max[a] - domain_.min[a];
      all_is = {std::min(all_is[0], r.is[0]), std::max(all_is[1], r.is[1])};
      all_js = {std::min(all_js[0], r.js[0]), std::max(all_js[1], r.js[1])};
    }
    if (all_is[0] > all_is[1]) continue;
    // Tiles of kTile × kTile rays, on a grid fixed to the family, are the unit of parallel work:
    // a tile applies every cut that reaches it, in order, to its rays. Each ray belongs to one
    // tile and its result depends on no other ray, and the tallies are summed in tile order, so
    // the outcome is the same for any number of threads.
    pass.ti0 = all_is[0] / kTile;
    pass.tj0 = all_js[0] / kTile;
    pass.nti = all_is[1] / kTile - pass.ti0 + 1;
    pass.ntj = all_js[1] / kTile - pass.tj0 + 1;
    tile_count += pass.tiles();
    // Each record's tiles are those its cuts reach; the stretches a tile takes for a cut go
    // straight to the same tile of the cut's record.
    for (const Owner& owner : owners) {
      std::array<int, 2> is{std::numeric_limits<int>::max(), -1}, js = is;
      for (std::size_t k = owner.first; k <= owner.last; ++k) {
        const Reach& r = pass.reach[k];
        if (r.is[0] > r.is[1] || r.js[0] > r.js[1]) continue;
        is = {std::min(is[0], r.is[0]), std::max(is[1], r.is[1])};
        js = {std::min(js[0], r.js[0]), std::max(js[1], r.js[1])};
      }
      RemovalRecord::Family& family = owner.record->families_[static_cast<std::size_t>(a)];
      if (is[0] > is[1]) continue;  // left with no tiles by clear()
      family.first_i = is[0] / kTile;
      family.first_j = js[0] / kTile;
      family.tiles_i = is[1] / kTile - family.first_i + 1;
      family.tiles_j = js[1] / kTile - family.first_j + 1;
      const auto tiles =
          static_cast<std::size_t>(family.tiles_i) * static_cast<std::size_t>(family.tiles_j);
      if (family.tiles.size() < tiles) family.tiles.resize(tiles);
    }
  }
  // Tile (ti, tj) of a record's family a, or null outside its tiles.
  const auto tile_of = [](RemovalRecord* record, int a, int ti, int tj) -> RemovalRecord::Tile* {
    RemovalRecord::Family& family = record->families_[static_cast<std::size_t>(a)];
    const int li = ti - family.first_i, lj = tj - family.first_j;
    if (li < 0 || lj < 0 || li >= family.tiles_i || lj >= family.tiles_j) return nullptr;
    return &family.tiles[static_cast<std::size_t>(lj) * static_cast<std::size_t>(family.tiles_i) +
                         static_cast<std::size_t>(li)];
  };
  // Tile t of a pass (numbered from its first) applies the cuts that reach it and tallies what
  // each took.
  const auto apply_tile = [&](const Pass& pass, std::size_t t,
                              std::vector<std::pair<std::size_t, Tally>>& tally) {
    const int a = pass.a, b = cross_b(a), c = cross_c(a);
    const std::vector<Reach>& reach = pass.reach;
    auto& family = rays_[static_cast<std::size_t>(a)];
    auto& free_spans = free_[static_cast<std::size_t>(a)];
    const int row_rays = grid_[static_cast<std::size_t>(a)][0];
    const int ti = pass.ti0 + static_cast<int>(t % static_cast<std::size_t>(pass.nti));
    const int tj = pass.tj0 + static_cast<int>(t / static_cast<std::size_t>(pass.nti));
    for (std::size_t k = 0; k < cuts.size(); ++k) {
      const Reach& r = reach[k];
      const int i0 = std::max(r.is[0], ti * kTile), i1 = std::min(r.is[1], ti * kTile + kTile - 1);
      const int j0 = std::max(r.js[0], tj * kTile), j1 = std::min(r.js[1], tj * kTile + kTile - 1);
      if (i0 > i1 || j0 > j1) continue;
      Tally sum;
      RemovalRecord::Tile* const taken =
          records[k] != nullptr ? tile_of(records[k], a, ti, tj) : nullptr;
      // Takes `chord` from ray (i, j).
      const auto take = [&](DexelRay& material, int i, int j, const Interval& chord) {
        if (chord.is_empty()) return;
        const auto before = static_cast<std::ptrdiff_t>(material.heap_bytes());
        // Each stretch taken is appended in place (subtract() hands them on from two places).
        auto append = [&](float lo, float hi) __attribute__((always_inline)) {
          taken->stretches.push_back({i, j, lo, hi});
        };
        const double removed = taken == nullptr
                                   ? material.subtract(chord.lo, chord.hi, [](float, float) {})
                                   : material.subtract(chord.lo, chord.hi, append);
        if (removed == 0.0) return;
        ++sum.changed;
        sum.length += removed;
        sum.heap += static_cast<std::ptrdiff_t>(material.heap_bytes()) - before;
      };
      const Cut& cut = cuts[k];
      // The last row's chords, with its key and rays: a row of the same key and rays has them.
      std::array<Interval, kTile> chords;
      std::array<int, kTile> chords_i;
      std::size_t chords_n = 0;
      double chords_key = std::numeric_limits<double>::quiet_NaN();
      for (int j = j0; j <= j1; ++j) {
        DexelRay* row = &family[index(a, 0, j)];
        // The row's rays as ray(a, i, j) makes them, without the index checks.
        const double oc = domain_.min[c] + (j + 0.5) * spacing_[c];
        const auto ray_at = [&](double ob) { return Ray{ray_origin(a, ob, oc), Vec3::Unit(a)}; };
        const Ray row_ray = ray_at(domain_.min[b]);  // for `rows`, which set each ray's b
        // A tile row whose rays hold no material within the box is skipped unread.
        FreeSpan& free = free_spans[free_row(a, j, ti)];
        if (free.lo <= r.low && r.high <= free.hi) continue;
        // The row's rays within the box and the cut's span across the row.
        int from = i0, to = i1;
        if (cut.row_span) {
          const Interval span = cut.row_span(row_ray, b);
          // The whole line (rows the cut has no span for) leaves the box's rays as they are.
          const std::array<int, 2> spanned = span == Interval::full()
                                                 ? std::array<int, 2>{from, to}
                                                 : index_range(a, b, span.lo, span.hi);
          from = std::max(from, spanned[0]);
          to = std::min(to, spanned[1]);
          if (from > to) continue;
        }
        // Up to the first ray with material within the box, the material's ends about it
        // (a loop of its own, which keeps the bounds in registers).
        float below = -std::numeric_limits<float>::infinity();
        float above = std::numeric_limits<float>::infinity();
        int first_hit = from;
        while (first_hit <= to && !row[first_hit].overlaps_or_bound(r.low, r.high, below, above)) {
          ++first_hit;
        }
        bool missed = first_hit > to;
        // The rays whose material the cut's box (and its reach) holds: with `rows`, gathered
        // for one call; without, each ray's chord at once.
        std::array<int, kTile> at_i;
        std::array<double, kTile> at;
        std::size_t n = 0;
        for (int i = first_hit; i <= to; ++i) {
          DexelRay& material = row[i];
          if (i > first_hit && !material.overlaps(r.low, r.high)) continue;
          const double ob = domain_.min[b] + (i + 0.5) * spacing_[b];
          if (cut.reach) {
            const Interval w = cut.reach(ray_at(ob));
            if (!material.overlaps(std::max(r.low, w.lo), std::min(r.high, w.hi))) {
              continue;
            }
          }
          if (cut.rows) {
            at_i[n] = i;
            at[n++] = ob;
          } else {
            take(material, i, j, cut.chord(ray_at(ob)));
          }
        }
        if (missed) {
          // The rest of the tile row: if none of it has material within the box either,
          // the row's free span is noted for the cuts to come.
          const int first = ti * kTile, last = std::min(first + kTile, row_rays) - 1;
          for (int i = first; missed && i <= last; ++i) {
            if (i == from) i = to + 1;
            if (i > last) break;
            missed = !row[i].overlaps_or_bound(r.low, r.high, below, above);
          }
          if (missed) free = {below, above};
          continue;
        }
        if (n == 0) continue;
        const double key =
            cut.row_key ? cut.row_key(row_ray, b) : std::numeric_limits<double>::quiet_NaN();
        if (!(key == chords_key && n == chords_n &&
              std::equal(at_i.begin(), at_i.begin() + static_cast<std::ptrdiff_t>(n),
                         chords_i.begin()))) {
          cut.rows(row_ray, b, {at.data(), n}, {chords.data(), n});
          chords_key = key;
          chords_n = n;
          chords_i = at_i;
        }
        for (std::size_t m = 0; m < n; ++m) take(row[at_i[m]], at_i[m], j, chords[m]);
      }
      if (sum.changed > 0) tally.emplace_back(k, sum);
    }
    // Unless deferred, every tile of a record is indexed, those its cuts left empty too. A
    // record of several cuts gets their stretches cut by cut, and sorts them by ray.
    if (indexing == Indexing::kDeferred) return;
    for (const Owner& owner : owners) {
      if (RemovalRecord::Tile* tile = tile_of(owner.record, a, ti, tj)) {
        RemovalRecord::index_tile(*tile, tj * kTile, owner.last > owner.first);
      }
    }
  };
  // The three families' tiles in one parallel pass (one fork and join, and a family's few large
  // tiles beside another's many small ones). A few tiles (a step between cutter locations) are
  // not worth a hand-off between threads; a few tiles that each apply a group of steps are.
  std::vector<std::vector<std::pair<std::size_t, Tally>>> tallies(tile_count);
  const auto apply = [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t t = range.begin(); t < range.end(); ++t) {
      const Pass& pass = t < passes[1].first   ? passes[0]
                         : t < passes[2].first ? passes[1]
                                               : passes[2];
      apply_tile(pass, t - pass.first, tallies[t]);
    }
  };
  const tbb::blocked_range<std::size_t> all_tiles(0, tile_count, 1);
  if (tile_count * cuts.size() <= kSerialTiles) {
    apply(all_tiles);
  } else {
    tbb::parallel_for(all_tiles, apply);
  }
  // Summed family by family in tile order, as the tiles were numbered.
  for (const Pass& pass : passes) {
    if (pass.tiles() == 0) continue;  // no cut reaches the family's rays
    for (std::size_t t = pass.first; t < pass.first + pass.tiles(); ++t) {
      for (const auto& [k, sum] : tallies[t]) {
        removals[k].rays += sum.changed;
        // The family's volume.
        lengths[k] += sum.length * spacing_[cross_b(pass.a)] * spacing_[cross_c(pass.a)];
        heap_bytes_ = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(heap_bytes_) + sum.heap);
      }
    }
    if (indexing == Indexing::kNow) {
      for (const Owner& owner : owners) owner.record->bound_family(pass.a, domain_.min, spacing_);
    }
  }
  // A deferred record keeps what its index() needs.
  if (indexing == Indexing::kDeferred) {
    for (const Owner& owner : owners) {
      owner.record->indexed_ = false;
      owner.record->sort_ = owner.last > owner.first;
      owner.record->origin_ = domain_.min;
      owner.record->spacing_ = spacing_;
    }
  }
  peak_heap_bytes_ = std::max(peak_heap_bytes_, heap_bytes_);
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    removals[k].volume = lengths[k] / 3.0;
  }
  return removals;
}

double TriDexel::Volume::spread() const {
  return *std::max_element(by_family.begin(), by_family.end()) -
         *std::min_element(by_family.begin(), by_family.end());
}

TriDexel::Volume TriDexel::volume() const {
  Volume v;
  // The families at once, each summed in ray order (the same sums for any number of threads):
  // the job's start and end ask it with nothing else to do.
  tbb::parallel_for(0, 3, [&](int a) {
    double length = 0.0;
    for (const DexelRay& r : rays_[static_cast<std::size_t>(a)]) length += r.length();
    v.by_family[static_cast<std::size_t>(a)] = length * spacing_[cross_b(a)] * spacing_[cross_c(a)];
  });
  return v;
}

bool TriDexel::contains(const Vec3& p) const {
  int votes = 0;
  for (int a = 0; a < 3; ++a) {
    const auto& g = grid_[static_cast<std::size_t>(a)];
    const int b = cross_b(a), c = cross_c(a);
    const auto i = static_cast<int>(std::floor((p[b] - domain_.min[b]) / spacing_[b]));
    const auto j = static_cast<int>(std::floor((p[c] - domain_.min[c]) / spacing_[c]));
    if (i < 0 || j < 0 || i >= g[0] || j >= g[1]) continue;
    if (at(a, i, j).contains(p[a] - domain_.min[a])) ++votes;
  }
  return votes >= 2;
}

double TriDexel::float_rounding() const {
  const auto longest = static_cast<float>(domain_.size().maxCoeff());
  return 0.5 * (static_cast<double>(std::nextafter(longest, std::numeric_limits<float>::max())) -
                static_cast<double>(longest));
}

TriDexel::Memory TriDexel::memory() const {
  Memory m;
  for (const auto& family : rays_) m.ray_bytes += family.size() * sizeof(DexelRay);
  for (const auto& spans : free_) m.span_bytes += spans.size() * sizeof(FreeSpan);
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

std::size_t TriDexel::free_rows() const {
  std::size_t rows = 0;
  for (const auto& spans : free_) {
    for (const FreeSpan& span : spans) rows += span.lo <= span.hi ? 1 : 0;
  }
  return rows;
}

}  // namespace cwe
