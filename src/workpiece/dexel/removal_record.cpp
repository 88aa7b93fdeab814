#include "cwe/workpiece/dexel/removal_record.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "cwe/core/assert.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace cwe {
namespace {

bool before(const RemovalRecord::Stretch& x, const RemovalRecord::Stretch& y) {
  if (x.j != y.j) return x.j < y.j;
  if (x.i != y.i) return x.i < y.i;
  return x.lo < y.lo;
}

}  // namespace

void RemovalRecord::clear() {
  for (Family& family : families_) {
    for (Tile& tile : family.tiles) tile.stretches.clear();  // keeps the buffers for the next step
    family.tiles_i = family.tiles_j = 0;
  }
  stretches_ = 0;
  bounds_ = Aabb();
  indexed_ = true;
}

void RemovalRecord::index() {
  if (indexed_) return;
  for (int a = 0; a < 3; ++a) {
    Family& family = families_[static_cast<std::size_t>(a)];
    for (int lj = 0; lj < family.tiles_j; ++lj) {
      for (int li = 0; li < family.tiles_i; ++li) {
        index_tile(
            family.tiles[static_cast<std::size_t>(lj) * static_cast<std::size_t>(family.tiles_i) +
                         static_cast<std::size_t>(li)],
            (family.first_j + lj) * kTileRows, sort_);
      }
    }
    bound_family(a, origin_, spacing_);
  }
  indexed_ = true;
}

void RemovalRecord::index_tile(Tile& tile, int first_j, bool sort) {
  auto& stretches = tile.stretches;
  if (sort) std::sort(stretches.begin(), stretches.end(), before);
  std::size_t k = 0;
  tile.single_rows = 0;
  for (int row = 0; row <= kTileRows; ++row) {
    while (k < stretches.size() && stretches[k].j < first_j + row) ++k;
    tile.rows[static_cast<std::size_t>(row)] = static_cast<std::uint32_t>(k);
    if (row == kTileRows) break;
    // The row's rays: which lost something, and whether any lost more than one stretch.
    std::uint32_t present = 0;
    bool single = true;
    for (std::size_t m = k; m < stretches.size() && stretches[m].j == first_j + row; ++m) {
      const std::uint32_t bit = std::uint32_t{1} << (stretches[m].i % kTileRows);
      single = single && (present & bit) == 0;
      present |= bit;
    }
    tile.present[static_cast<std::size_t>(row)] = present;
    if (single) tile.single_rows |= std::uint32_t{1} << row;
  }
}

void RemovalRecord::bound_family(int axis, const Vec3& origin, const Vec3& spacing) {
  const int a = axis, b = (a + 1) % 3, c = (a + 2) % 3;
  const Family& taken = families_[static_cast<std::size_t>(a)];
  const auto tiles =
      static_cast<std::size_t>(taken.tiles_i) * static_cast<std::size_t>(taken.tiles_j);
  for (std::size_t t = 0; t < tiles; ++t) {
    const Tile& tile = taken.tiles[t];
    if (tile.stretches.empty()) continue;
    stretches_ += tile.stretches.size();
    // The tile's box: its rays' extent across the family, its stretches' along it.
    float lo = tile.stretches.front().lo, hi = tile.stretches.front().hi;
    int i0 = tile.stretches.front().i, i1 = i0;
    for (const Stretch& s : tile.stretches) {
      lo = std::min(lo, s.lo);
      hi = std::max(hi, s.hi);
      i0 = std::min(i0, s.i);
      i1 = std::max(i1, s.i);
    }
    Aabb box;
    box.min[a] = origin[a] + lo;
    box.max[a] = origin[a] + hi;
    box.min[b] = origin[b] + (i0 + 0.5) * spacing[b];
    box.max[b] = origin[b] + (i1 + 0.5) * spacing[b];
    box.min[c] = origin[c] + (tile.stretches.front().j + 0.5) * spacing[c];
    box.max[c] = origin[c] + (tile.stretches.back().j + 0.5) * spacing[c];
    bounds_.extend(box);
  }
}

std::size_t RemovalRecord::held_bytes() const {
  std::size_t bytes = 0;
  for (const Family& family : families_) {
    bytes += family.tiles.capacity() * sizeof(Tile);
    for (const Tile& tile : family.tiles) bytes += tile.stretches.capacity() * sizeof(Stretch);
  }
  return bytes;
}

void RemovalRecord::release() {
  for (Family& family : families_) family = Family();
  stretches_ = 0;
  bounds_ = Aabb();
  indexed_ = true;
}

static_assert(RemovalRecord::kTileRows == TriDexel::kTile, "a record's tiles are the removal's");

bool RemovalRecord::alike(int axis, int across, int a, int b) const {
  CWE_ASSERT(indexed_, "a removal record read before index()");
  CWE_ASSERT(a >= 0 && b >= 0, "alike compares rays of the grid");
  if (a == b) return true;
  const Family& family = families_[static_cast<std::size_t>(axis)];
  const auto same_ends = [](const Stretch& p, const Stretch& q) {
    return p.lo == q.lo && p.hi == q.hi;
  };
  // Two rows' stretches, ray by ray (the rays' i, then the ends).
  const auto same = [&same_ends](std::span<const Stretch> x, std::span<const Stretch> y) {
    return std::equal(
        x.begin(), x.end(), y.begin(), y.end(),
        [&](const Stretch& p, const Stretch& q) { return p.i == q.i && same_ends(p, q); });
  };
  const auto row_of = [](const Tile* tile, int row) -> std::span<const Stretch> {
    if (tile == nullptr) return {};
    return {tile->stretches.data() + tile->rows[static_cast<std::size_t>(row)],
            tile->stretches.data() + tile->rows[static_cast<std::size_t>(row) + 1]};
  };
  if (across == 1) {
    // Rows j = a and j = b: tile by tile along i, the same stretches in order (by ray).
    for (int ti = family.first_i; ti < family.first_i + family.tiles_i; ++ti) {
      if (!same(row_of(tile_at(family, ti, a / kTileRows), a % kTileRows),
                row_of(tile_at(family, ti, b / kTileRows), b % kTileRows))) {
        return false;
      }
    }
    return true;
  }
  // Columns i = a and i = b: row by row, the two rays' stretches.
  const std::uint32_t bit_a = std::uint32_t{1} << (a % kTileRows);
  const std::uint32_t bit_b = std::uint32_t{1} << (b % kTileRows);
  for (int tj = family.first_j; tj < family.first_j + family.tiles_j; ++tj) {
    const Tile* const p = tile_at(family, a / kTileRows, tj);
    const Tile* const q = tile_at(family, b / kTileRows, tj);
    for (std::size_t row = 0; row < kTileRows; ++row) {
      const bool in_a = p != nullptr && (p->present[row] & bit_a) != 0;
      const bool in_b = q != nullptr && (q->present[row] & bit_b) != 0;
      if (in_a != in_b) return false;
      if (!in_a) continue;
      const std::span<const Stretch> x = in_row(*p, row, a), y = in_row(*q, row, b);
      if (!std::equal(x.begin(), x.end(), y.begin(), y.end(), same_ends)) return false;
    }
  }
  return true;
}

std::vector<RemovalRecord::Stretch> RemovalRecord::family(int axis) const {
  CWE_ASSERT(indexed_, "a removal record read before index()");
  const Family& family = families_[static_cast<std::size_t>(axis)];
  std::vector<Stretch> all;
  for (std::size_t t = 0; t < static_cast<std::size_t>(family.tiles_i * family.tiles_j); ++t) {
    all.insert(all.end(), family.tiles[t].stretches.begin(), family.tiles[t].stretches.end());
  }
  std::sort(all.begin(), all.end(), before);
  return all;
}

}  // namespace cwe
