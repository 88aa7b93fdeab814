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
