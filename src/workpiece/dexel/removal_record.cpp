#include "cwe/workpiece/dexel/removal_record.hpp"

#include <algorithm>
#include <limits>

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

std::span<const RemovalRecord::Stretch> RemovalRecord::on_ray(int axis, int i, int j) const {
  const Family& family = families_[static_cast<std::size_t>(axis)];
  const int ti = i / TriDexel::kTile - family.first_i, tj = j / TriDexel::kTile - family.first_j;
  if (i < 0 || j < 0 || ti < 0 || tj < 0 || ti >= family.tiles_i || tj >= family.tiles_j) {
    return {};
  }
  const Tile& tile =
      family.tiles[static_cast<std::size_t>(tj) * static_cast<std::size_t>(family.tiles_i) +
                   static_cast<std::size_t>(ti)];
  // The ray's row of the tile, then the ray within the row.
  const int row = j - (family.first_j + tj) * TriDexel::kTile;
  const Stretch* first = tile.stretches.data() + tile.rows[static_cast<std::size_t>(row)];
  const Stretch* const end = tile.stretches.data() + tile.rows[static_cast<std::size_t>(row) + 1];
  first = std::lower_bound(first, end, i, [](const Stretch& s, int ray) { return s.i < ray; });
  const Stretch* last = first;
  while (last != end && last->i == i) ++last;
  return {first, last};
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
