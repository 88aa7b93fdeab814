#include "cwe/workpiece/dexel/removal_record.hpp"

#include <algorithm>
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
}

static_assert(RemovalRecord::kTileRows == TriDexel::kTile, "a record's tiles are the removal's");

bool RemovalRecord::alike(int axis, int across, int a, int b) const {
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
  const Family& family = families_[static_cast<std::size_t>(axis)];
  std::vector<Stretch> all;
  for (std::size_t t = 0; t < static_cast<std::size_t>(family.tiles_i * family.tiles_j); ++t) {
    all.insert(all.end(), family.tiles[t].stretches.begin(), family.tiles[t].stretches.end());
  }
  std::sort(all.begin(), all.end(), before);
  return all;
}

}  // namespace cwe
