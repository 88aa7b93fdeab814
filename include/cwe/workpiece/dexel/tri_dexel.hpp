#pragma once
// The tri-dexel in-process workpiece (Aras 2008 ch. 4): three orthogonal families of rays at
// spacing s, each ray holding the material along it as sorted, disjoint intervals (DexelRay).
//
// Geometry of the grid: the domain is the stock's box, cut along each axis a into a whole number
// of cells of side s_a = (box side) / ⌈(box side) / s⌉ ≤ s, so that the cells tile the box
// exactly whatever its size. The family along axis a (its rays parallel to a) has one ray
// through the centre of every s_b × s_c cell of the domain's face across a: with (b, c) the two
// other axes in cyclic order, ray (i, j) starts on the domain's lower face at
// min + (i + ½)s_b·e_b + (j + ½)s_c·e_c and runs along +e_a; its coordinate t is the distance
// from that face (mm), and it stands for the material of its cell's prism (length × s_b × s_c).
//
// Material removal takes the solid to remove as a chord function: for a ray (origin, unit
// direction), the interval of t inside the solid (one interval: every swept volume of a convex
// APT cutter along a linear move is convex). Only rays whose line meets the solid's bounding box
// are visited.

#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/ray.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/workpiece/dexel/dexel_ray.hpp"
#include "cwe/workpiece/dexel/removal_record.hpp"

namespace cwe {

class TriDexel {
 public:
  // A block of stock filling `box`, rays every `spacing` mm. Throws InputError for an empty box
  // or a spacing that is not positive, would need more than kMaxRaysPerFamily rays, or rays
  // beyond the memory limit (cwe/core/memory_limit.hpp), all before allocating.
  static TriDexel from_box(const Aabb& box, double spacing);

  // Stock filling a closed triangle mesh (its bounding box is the stock box), rays every
  // `spacing` mm, by exact scan conversion: every ray collects its crossings with the triangles
  // and keeps the stretches of non-zero winding number (so an inside-out mesh is read as its
  // solid, and a void inside a part stays empty).
  // Robustness: vertices are snapped to a fixed grid of spacing s_a/2²⁰ (shifts ≤ 5e-8 mm at
  // s = 0.1) on which the ray centres lie exactly, the inside-triangle tests are exact integer
  // arithmetic, and a ray through an edge or vertex is decided by symbolic perturbation of the
  // ray's position: it crosses exactly one of the triangles sharing the edge or vertex, so no ray
  // leaks through the mesh and none counts a crossing twice. Crossing coordinates are
  // interpolated on the triangle (exact for faces square to the ray: a box-shaped mesh gives
  // the same rays as from_box).
  // Throws InputError naming `source` when the mesh is not closed (the counts of boundary,
  // non-manifold and inconsistently oriented edges, and where the first ones are), or for a
  // bad spacing as from_box.
  static TriDexel from_mesh(const TriangleMesh& mesh, double spacing, const std::string& source);

  static constexpr std::size_t kMaxRaysPerFamily = std::size_t{1} << 31;
  // What from_box and from_mesh check before allocating: InputError at `where` (the option or
  // job-file key that gave the spacing) when a stock box at `spacing` would need more than 1e7
  // cells along an axis, more than kMaxRaysPerFamily rays in one family, or rays
  // (sizeof(DexelRay) bytes each, and a FreeSpan for each kTile of a row) beyond the memory
  // limit. `spacing` must be positive.
  static void check_grid(const Aabb& box, double spacing, const SourceLocation& where = {});

  // The ray spacing: the largest cell side (at most the spacing asked for).
  double spacing() const { return spacing_.maxCoeff(); }
  // The cell side along `axis` (the spacing of the rays across it).
  double spacing(int axis) const { return spacing_[axis]; }
  const Aabb& domain() const { return domain_; }
  // Rays of family `axis` along its two cross axes (b, c) in cyclic order.
  std::array<int, 2> grid(int axis) const { return grid_[static_cast<std::size_t>(axis)]; }
  std::size_t ray_count() const;

  Ray ray(int axis, int i, int j) const;
  const DexelRay& at(int axis, int i, int j) const;
  // The rays (i, j) of family `axis` for i = 0 … grid(axis)[0] − 1, in that order: a scan of
  // every ray without an index check each.
  std::span<const DexelRay> row(int axis, int j) const;

  // Removes the solid given by `chord` from every ray whose line meets `bounds`. Returns the
  // number of rays that changed and the volume removed (the mean of the families' measures). Rays
  // are visited in parallel (oneTBB) in tiles of kTile × kTile, so `chord` must be safe to call
  // concurrently; the result is the same for any thread count. Rays without material inside
  // `bounds` are skipped without calling `chord`.
  using ChordFunction = std::function<Interval(const Ray&)>;
  static constexpr int kTile = 32;
  // Removals whose tiles (the three families' together) times their cuts come to at most this
  // run on the calling thread.
  static constexpr std::size_t kSerialTiles = 8;
  struct Removal {
    std::size_t rays = 0;
    double volume = 0.0;  // mm³
  };
  Removal remove(const Aabb& bounds, const ChordFunction& chord);
  // Several solids removed one after the other, as by one remove() each, with one parallel pass:
  // each tile applies, in order, every cut that reaches it, so its rays stay in cache across the
  // cuts, and there is one fork and join for the three families instead of one per cut. Returns
  // each cut's removal (what it took that the earlier cuts had not). The memory peak is sampled at
  // the end. When `record` is given it is cleared and receives every stretch of material taken, ray
  // by ray (the same for any thread count).
  struct Cut {
    Aabb bounds;
    ChordFunction chord;
    // Optional: an interval of the ray's parameter that holds the chord, cheaper than the chord
    // itself; a ray whose material misses it is skipped without calling `chord`.
    ChordFunction reach;
    // Optional: `chord` for a row of rays at once, which removal then calls instead, once per
    // row of a tile. The rays differ only in their origin's coordinate along world axis
    // `across`: ray k has origin[across] = at[k], and its chord goes to chords[k].
    std::function<void(const Ray& ray, int across, std::span<const double> at,
                       std::span<Interval> chords)>
        rows;
    // Optional, with `rows`: what a row's chords depend on besides `at`, where that is one
    // number (NaN otherwise): rows of one family with the same key and the same `at` get the
    // chords of the first, without a call.
    std::function<double(const Ray& ray, int across)> row_key = {};
    // Optional: for a row of rays as `rows` has them, an interval of origin[across] outside
    // which every ray's chord is empty; those rays are not visited.
    std::function<Interval(const Ray& ray, int across)> row_span = {};
  };
  std::vector<Removal> remove(const std::vector<Cut>& cuts, RemovalRecord* record = nullptr);
  // The same with a record per cut: records[k] (null for none) receives what cut k took, and
  // cuts that share a record must follow one another. So the steps between several cutter
  // locations are removed in one parallel pass, each into its own record, with every ray and
  // record as removing them one call after the other gives. With `indexing` kDeferred, each
  // record waits for its RemovalRecord::index() before it may be read.
  enum class Indexing { kNow, kDeferred };
  std::vector<Removal> remove(const std::vector<Cut>& cuts, std::span<RemovalRecord* const> records,
                              Indexing indexing = Indexing::kNow);

  // Material volume as each family measures it (Σ lengths × s²), mm³.
  struct Volume {
    std::array<double, 3> by_family{};
    double mean() const { return (by_family[0] + by_family[1] + by_family[2]) / 3.0; }
    double spread() const;  // largest minus smallest family estimate
  };
  Volume volume() const;

  // Material at p: the vote of the three rays nearest p (two of three).
  bool contains(const Vec3& p) const;

  // The ray that reads a surface through `point` with unit outward `normal`: of the family most
  // nearly along the normal (|n_a| ≥ 1/√3), the one passing nearest the point (within s/√2).
  // `along` is the normal's component n_a along the ray (its sign says which way along the ray
  // is outward); meet() is the ray coordinate where it meets the surface's tangent plane. False
  // when the point's nearest ray would lie outside the grid. (Filled in place: a ray copied out
  // right after its origin was written coordinate by coordinate stalled on the stores.)
  struct SurfaceRay {
    int axis = 0;
    int i = 0, j = 0;  // the ray's indices across its family, as at(axis, i, j)
    Vec3 origin = Vec3::Zero();
    double along = 1.0;
    // Apart from the rest: a caller that finds nothing on the ray never pays its division.
    double meet(const Vec3& point, const Vec3& normal) const {
      return (point - origin).dot(normal) / along;
    }
  };
  // Inline: engagement asks it for every cell of the cutter surface that moves into material.
  [[gnu::always_inline]] bool surface_ray(const Vec3& point, const Vec3& normal,
                                          SurfaceRay& ray) const {
    int a = 0;
    for (int k = 1; k < 3; ++k) {
      if (std::abs(normal[k]) > std::abs(normal[a])) a = k;
    }
    if (!(std::abs(normal[a]) > 0.0)) return false;
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const auto& g = grid_[static_cast<std::size_t>(a)];
    const double fi = cell_floor(point[b] - domain_.min[b], b);
    const double fj = cell_floor(point[c] - domain_.min[c], c);
    if (!(fi >= 0.0 && fj >= 0.0 && fi < g[0] && fj < g[1])) return false;
    ray.axis = a;
    ray.i = static_cast<int>(fi);
    ray.j = static_cast<int>(fj);
    ray.origin = ray_origin(a, domain_.min[b] + (fi + 0.5) * spacing_[b],
                            domain_.min[c] + (fj + 0.5) * spacing_[c]);
    ray.along = normal[a];
    return true;
  }

  // The rays of the two horizontal families (X and Y) that surface_ray reads for a point at
  // height z: their index along Z (j of an X ray, i of a Y ray) and their height, exactly as
  // surface_ray makes them; false where z is outside the grid.
  bool level_at(double z, int& level, double& ray_z) const {
    const double f = cell_floor(z - domain_.min[2], 2);
    if (!(f >= 0.0 && f < grid_[0][1])) return false;
    level = static_cast<int>(f);
    ray_z = domain_.min[2] + (f + 0.5) * spacing_[2];
    return true;
  }

  // ⌊x / s⌋ along `axis`, exactly as the division gives it (a point on a cell border, as a CAM
  // program's round coordinates put it, must fall in the same cell everywhere in the code), but
  // from x · (1/s): the product is within 3 ulps of the quotient, so the two floors can differ
  // only where the product lies that close to a whole number, and there the division decides.
  [[gnu::always_inline]] double cell_floor(double x, int axis) const {
    const double q = x * inverse_spacing_[axis];
    const double f = std::floor(q);
    const double border = 1e-13 * (1.0 + std::abs(q));
    if (q - f > border && (f + 1.0) - q > border) return f;
    return std::floor(x / spacing_[axis]);
  }

  // The largest rounding of a stored ray end: half the spacing of floats at the domain's
  // longest side (about 4e-6 mm for a 100 mm stock). Lengths below a few of these are rounding.
  double float_rounding() const;

  // Bytes held by the rays, kept up to date by every change (no scan needed).
  struct Memory {
    std::size_t ray_bytes = 0;        // 16 per ray
    std::size_t span_bytes = 0;       // 8 per kTile rays of a row (the rows' free spans)
    std::size_t heap_bytes = 0;       // 8 per interval beyond two on a ray
    std::size_t peak_heap_bytes = 0;  // the most heap_bytes has been
    std::size_t total() const { return ray_bytes + span_bytes + heap_bytes; }
    std::size_t peak() const { return ray_bytes + span_bytes + peak_heap_bytes; }
  };
  Memory memory() const;
  // Heap bytes counted ray by ray (tests hold the running count to it).
  std::size_t count_heap_bytes() const;
  // Tile rows (kTile rays of a row) with a free span noted, which later cuts may skip unread.
  std::size_t free_rows() const;

 private:
  // The origin of a family-`a` ray at cross coordinates ob (along b = a + 1) and oc (along
  // c = a + 2), made whole from registers: an origin written coordinate by coordinate and read
  // back at once as a vector (as Eigen's arithmetic reads it) stalls the load on the stores.
  [[gnu::always_inline]] Vec3 ray_origin(int a, double ob, double oc) const {
    const int b = (a + 1) % 3;
    return {a == 0 ? domain_.min.x() : (b == 0 ? ob : oc),
            a == 1 ? domain_.min.y() : (b == 1 ? ob : oc),
            a == 2 ? domain_.min.z() : (b == 2 ? ob : oc)};
  }
  // The grid for stock in `box` (whole cells that tile it), with empty rays, or with every ray
  // full across the box (`filled`).
  static TriDexel empty_grid(const Aabb& box, double spacing, bool filled = false);
  std::size_t index(int axis, int i, int j) const;
  // Range of ray indices along one cross axis whose lines come within [lo, hi].
  std::array<int, 2> index_range(int axis, int cross, double lo, double hi) const;

  Aabb domain_;
  Vec3 spacing_ = Vec3::Ones();          // cell side per axis
  Vec3 inverse_spacing_ = Vec3::Ones();  // 1 / spacing_ (cell_floor)
  std::array<std::array<int, 2>, 3> grid_{};
  std::array<std::vector<DexelRay>, 3> rays_;
  // For each family, row j and tile column: an open stretch of the ray coordinate in which none
  // of that tile row's kTile rays holds material, noted when a cut's visit found none of them
  // with material within its box; {+∞, −∞} until then. Removal only ever takes material away, so
  // a span once true stays true, and a later cut whose box lies within it skips the row's rays
  // without loading them (most rays a step's box reaches were emptied by the steps before).
  struct FreeSpan {
    float lo, hi;
  };
  std::array<std::vector<FreeSpan>, 3> free_;
  std::size_t free_row(int axis, int j, int tile_i) const {
    const auto tiles =
        static_cast<std::size_t>((grid_[static_cast<std::size_t>(axis)][0] + kTile - 1) / kTile);
    return static_cast<std::size_t>(j) * tiles + static_cast<std::size_t>(tile_i);
  }
  std::size_t heap_bytes_ = 0;
  std::size_t peak_heap_bytes_ = 0;
};

}  // namespace cwe
