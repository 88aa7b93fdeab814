#pragma once
// What one TriDexel::remove took from the rays: for every ray it changed, the stretches of
// material removed, in that ray's own coordinate (mm from the domain's lower face) and exactly as
// the ray stored them (float ends). For the removal of one step of a move this is the step's
// removal volume W ∩ SV (Aras 2008 eq. 6.3) as dexel segments, which is what engagement reads:
// a cutter point is engaged where the step removes material next to it.
//
// Storage follows the removal's parallel tiles (TriDexel::kTile × kTile rays), each tile's
// stretches sorted by ray with the start of each row of rays and a mask of the row's rays that
// lost something, so that recording costs no sort of the whole step and a look-up is a bit test,
// then a count of the bits below (a row whose rays lost one stretch each) or a short binary
// search within the row. A record reused for step after step keeps its buffers.
//
// TriDexel::remove indexes a record as it fills it, or, when asked, leaves the index (and the
// record's bounds and count) to index(): the main loop indexes each step's record beside its
// engagement, off the path of the removals that follow. Only index() may be called on a record
// that waits for it.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

class RemovalRecord {
 public:
  struct Stretch {
    int i = 0, j = 0;  // the ray's indices across its family (TriDexel::at(axis, i, j))
    float lo = 0.0f, hi = 0.0f;
  };
  static constexpr int kTileRows = 32;  // rays along a tile's side: TriDexel::kTile

  void clear();
  // Whether the record is ready to read, and its indexing where it is not (once; a no-op on a
  // ready record).
  bool indexed() const { return indexed_; }
  void index();
  // Bytes the record holds (its buffers, kept by clear() for the next step), and a release of
  // them all (a record that once held a large step need not keep that much).
  std::size_t held_bytes() const;
  void release();
  bool empty() const {
    CWE_ASSERT(indexed_, "a removal record read before index()");
    return stretches_ == 0;
  }
  // A box holding every stretch (empty when nothing was removed).
  const Aabb& bounds() const {
    CWE_ASSERT(indexed_, "a removal record read before index()");
    return bounds_;
  }
  // The stretches removed from ray (i, j) of family `axis` (0 x, 1 y, 2 z), ascending. Inline:
  // engagement asks it for every cell of the cutter surface that moves into material.
  [[gnu::always_inline]] std::span<const Stretch> on_ray(int axis, int i, int j) const {
    if (i < 0 || j < 0) return {};
    const Tile* tile =
        tile_at(families_[static_cast<std::size_t>(axis)], i / kTileRows, j / kTileRows);
    if (tile == nullptr) return {};
    return in_row(*tile, static_cast<std::size_t>(j % kTileRows), i);
  }
  // Whether the rays of family `axis` whose index `across` (0: i, 1: j) is `a` lost what those
  // whose index is `b` lost: ray for ray along the other index, the same stretches (their ends
  // compared exactly). a, b ≥ 0 (rays of the grid or beyond its far side, which lost nothing).
  bool alike(int axis, int across, int a, int b) const;
  // Every stretch of a family, sorted by ray (j, then i) and then by position.
  std::vector<Stretch> family(int axis) const;

 private:
  friend class TriDexel;
  // One tile's stretches, sorted by ray, and where each of its rows of rays (j) starts.
  struct Tile {
    std::vector<Stretch> stretches;
    std::array<std::uint32_t, kTileRows + 1> rows{};
    // Per row, a bit for each ray (i mod kTileRows) that lost something.
    std::array<std::uint32_t, kTileRows> present{};
    std::uint32_t single_rows = 0;  // a bit for each row whose rays lost one stretch at most
  };
  struct Family {
    int first_i = 0, first_j = 0;  // the first tile's indices (tile units)
    int tiles_i = 0, tiles_j = 0;  // tiles along i and j
    std::vector<Tile> tiles;
  };
  // The stretches of ray i in row `row` of `tile`: most rays lost nothing, which the row's mask
  // says at once; in a row where every ray lost one stretch at most, the ray's stretch is
  // counted from the mask.
  [[gnu::always_inline]] static std::span<const Stretch> in_row(const Tile& tile, std::size_t row,
                                                                int i) {
    const std::uint32_t mask = tile.present[row];
    const std::uint32_t bit = std::uint32_t{1} << (i % kTileRows);
    if ((mask & bit) == 0) return {};
    const Stretch* first = tile.stretches.data() + tile.rows[row];
    if ((tile.single_rows >> row & 1u) != 0) {
      return {first + rays_below(mask & (bit - 1)), 1};
    }
    const Stretch* const end = tile.stretches.data() + tile.rows[row + 1];
    // std::lower_bound without branches on the comparisons (they mispredicted at every step):
    // halve the range, keeping its upper half while the ray at its middle is below i.
    for (std::size_t n = static_cast<std::size_t>(end - first); n > 1;) {
      const std::size_t half = n / 2;
      first = first[half].i < i ? first + half : first;
      n -= half;
    }
    if (first->i < i) ++first;
    const Stretch* last = first;
    while (last != end && last->i == i) ++last;
    return {first, last};
  }
  // Sorts a tile's stretches by ray (when several cuts filled it, cut after cut) and indexes its
  // rows; `first_j` is the j of its first row of rays.
  static void index_tile(Tile& tile, int first_j, bool sort);
  // Adds family `axis`'s stretches to the count and the bounds, for a grid whose rays of that
  // family start at `origin` (the domain's lower corner) and lie `spacing` apart.
  void bound_family(int axis, const Vec3& origin, const Vec3& spacing);
  // Tile (ti, tj) of a family (tile units), or null outside its tiles.
  [[gnu::always_inline]] static const Tile* tile_at(const Family& family, int ti, int tj) {
    const int li = ti - family.first_i, lj = tj - family.first_j;
    if (li < 0 || lj < 0 || li >= family.tiles_i || lj >= family.tiles_j) return nullptr;
    return &family.tiles[static_cast<std::size_t>(lj) * static_cast<std::size_t>(family.tiles_i) +
                         static_cast<std::size_t>(li)];
  }
  // The bits set in `mask`, without the call std::popcount makes on the x86-64 baseline.
  [[gnu::always_inline]] static int rays_below(std::uint32_t mask) {
    mask -= (mask >> 1) & 0x55555555u;
    mask = (mask & 0x33333333u) + ((mask >> 2) & 0x33333333u);
    mask = (mask + (mask >> 4)) & 0x0f0f0f0fu;
    return static_cast<int>((mask * 0x01010101u) >> 24);
  }
  std::array<Family, 3> families_;
  std::size_t stretches_ = 0;
  Aabb bounds_;
  // What index() needs: whether the tiles hold several cuts' stretches, and the grid's.
  bool indexed_ = true;
  bool sort_ = false;
  Vec3 origin_ = Vec3::Zero(), spacing_ = Vec3::Ones();
};

}  // namespace cwe
