#include "cwe/workpiece/dexel/tri_dexel.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// The chord function of a cutter standing at `tip` with axis +Z (the tool solid itself).
TriDexel::ChordFunction tool_at(const Cutter& cutter, const Vec3& tip) {
  return [&cutter, tip](const Ray& ray) {
    const auto chords = cutter.intersect(Ray{ray.origin - tip, ray.direction});
    return chords.empty() ? Interval::empty() : hull(chords.front(), chords.back());
  };
}

TEST(TriDexel, BoxStockVolumeAndGrid) {
  const TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {10, 6, 4}}, 0.5);
  EXPECT_EQ(d.grid(2), (std::array<int, 2>{20, 12}));  // Z rays over the x-y face
  EXPECT_EQ(d.grid(0), (std::array<int, 2>{12, 8}));   // X rays over y-z
  EXPECT_EQ(d.ray_count(), 20u * 12u + 12u * 8u + 8u * 20u);
  for (const double v : d.volume().by_family) EXPECT_NEAR(v, 240.0, 1e-9);
  EXPECT_EQ(d.memory().ray_bytes, 16u * d.ray_count());
  // A free span of 8 bytes for each row of each family's tiles (one tile across here).
  EXPECT_EQ(d.memory().span_bytes, 8u * (12u + 8u + 20u));
  EXPECT_EQ(d.memory().heap_bytes, 0u);
  EXPECT_EQ(d.free_rows(), 0u);  // none known before a cut
  EXPECT_TRUE(d.contains(Vec3(5, 3, 2)));
  EXPECT_FALSE(d.contains(Vec3(5, 3, 4.5)));
  const Ray r = d.ray(2, 0, 0);
  EXPECT_TRUE(r.origin.isApprox(Vec3(0.25, 0.25, 0)));
  EXPECT_TRUE(r.direction.isApprox(Vec3::UnitZ()));
}

// cell_floor is ⌊x / s⌋ as the division rounds it, for every x: on cell borders (k·s as a
// program's round numbers give them, and the doubles next to them), where x · (1/s) alone goes
// wrong (0.3 / 0.1 = 2.9999999999999996 but 0.3 · 10 = 3), and anywhere else.
TEST(TriDexel, CellFloorIsTheDivisionsFloor) {
  test::Random random;
  for (const double spacing : {0.1, 0.07, 0.05, 0.3, 1.0 / 3.0}) {
    const TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {100, 50, 20}}, spacing);
    for (int a = 0; a < 3; ++a) {
      const double s = d.spacing(a);
      const auto check = [&](double x) {
        ASSERT_EQ(d.cell_floor(x, a), std::floor(x / s)) << "x = " << x << ", s = " << s;
      };
      for (int k = -2; k < 2100; ++k) {
        for (const double x : {k * s, k * 0.1, k * 0.05, k / 3.0}) {
          check(x);
          check(std::nextafter(x, -1e9));
          check(std::nextafter(x, 1e9));
        }
      }
      for (int k = 0; k < 20000; ++k) check(random.uniform(-1.0, 110.0));
    }
  }
  // The product alone would miss: 0.3 lies in cell 2 of 0.1 mm cells.
  const TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {100, 100, 100}}, 0.1);
  EXPECT_EQ(d.cell_floor(0.3, 0), 2.0);
}

TEST(TriDexel, RejectsBadStock) {
  EXPECT_THROW(TriDexel::from_box(Aabb{}, 1.0), InputError);
  EXPECT_THROW(TriDexel::from_box(Aabb{{0, 0, 0}, {1, 0, 1}}, 1.0), InputError);
  EXPECT_THROW(TriDexel::from_box(Aabb{{0, 0, 0}, {1, 1, 1}}, 0.0), InputError);
  EXPECT_THROW(TriDexel::from_box(Aabb{{0, 0, 0}, {1e6, 1e6, 1e6}}, 1e-3), InputError);
}

// Removing a flat end mill standing 5 mm deep in the block: every ray equals the box chord minus
// the exact cylinder chord (float rounding, 1e-5 mm), and the volumes approach π R² depth.
TEST(TriDexel, RemovingAToolIsExactPerRay) {
  TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {20, 20, 10}}, 0.1);
  const Cutter flat = cutter_from_spec("flat:6,20");
  const Vec3 tip(10.03, 9.97, 5.0);
  const TriDexel::Removal removal =
      d.remove(Aabb{tip - Vec3(3, 3, 0), tip + Vec3(3, 3, 20)}, tool_at(flat, tip));
  EXPECT_GT(removal.rays, 0u);
  // The reported volume is what the families measure.
  EXPECT_NEAR(removal.volume, 4000.0 - d.volume().mean(), 1e-9 * 4000.0);
  for (int j = 0; j < d.grid(0)[1]; ++j) {
    for (int i = 0; i < d.grid(0)[0]; ++i) {
      const Ray r = d.ray(0, i, j);  // along X at (y, z)
      const double dy = r.origin.y() - tip.y();
      const bool cut = r.origin.z() >= tip.z() && std::abs(dy) < 3.0;
      const auto got = d.at(0, i, j).intervals();
      if (!cut) {
        ASSERT_EQ(got.size(), 1u);
        continue;
      }
      const double half = std::sqrt(9.0 - dy * dy);
      ASSERT_EQ(got.size(), 2u) << "y " << r.origin.y() << " z " << r.origin.z();
      EXPECT_NEAR(got[0].hi, tip.x() - half, 1e-5);
      EXPECT_NEAR(got[1].lo, tip.x() + half, 1e-5);
    }
  }
  // Each family measures the removed cylinder (π·9·5 ≈ 141.4 mm³) to within the cells its
  // boundary crosses: perimeter × depth × spacing bounds the misattributed volume.
  const double removed_exact = kPi * 9.0 * 5.0;
  const double bound = 2 * kPi * 3.0 * 5.0 * 0.1;
  for (const double v : d.volume().by_family) EXPECT_NEAR(4000.0 - v, removed_exact, bound);
  EXPECT_NEAR(4000.0 - d.volume().mean(), removed_exact, bound / 3);
  EXPECT_FALSE(d.contains(tip + Vec3(0, 0, 1)));
  EXPECT_TRUE(d.contains(tip + Vec3(0, 0, -1)));
  EXPECT_TRUE(d.contains(tip + Vec3(3.5, 0, 1)));
}

// Property: removal never adds material and memory follows the interval counts.
TEST(TriDexel, RemovalNeverAddsMaterial) {
  test::Random random(52);
  TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {12, 12, 6}}, 0.2);
  const Cutter ball = cutter_from_spec("ball:3,10");
  TriDexel::Volume previous = d.volume();
  for (int k = 0; k < 40; ++k) {
    const Vec3 tip(random.uniform(0, 12), random.uniform(0, 12), random.uniform(2, 6));
    d.remove(Aabb{tip - Vec3(1.5, 1.5, 0), tip + Vec3(1.5, 1.5, 10)}, tool_at(ball, tip));
    const TriDexel::Volume v = d.volume();
    for (std::size_t a = 0; a < 3; ++a) EXPECT_LE(v.by_family[a], previous.by_family[a]);
    previous = v;
  }
  const TriDexel::Memory m = d.memory();
  EXPECT_EQ(m.ray_bytes, 16u * d.ray_count());
  EXPECT_EQ(m.heap_bytes % 8, 0u);
  // The running count of heap bytes is the count ray by ray.
  EXPECT_EQ(m.heap_bytes, d.count_heap_bytes());
  EXPECT_GE(m.peak_heap_bytes, m.heap_bytes);
  EXPECT_GT(m.peak_heap_bytes, 0u);
}

// Removing several solids in one call is removing them one after the other: the same rays, bit
// for bit, and the same per-solid removals (each solid's tallies summed in the same tile order),
// also when the batch takes its chords a row of rays at a time.
TEST(TriDexel, BatchedRemovalEqualsOneByOne) {
  test::Random random(53);
  const Cutter bull = cutter_from_spec("bull:4,1,12");
  std::vector<LinearSweep> sweeps;
  Vec3 at(2, 2, 5);
  for (int k = 0; k < 30; ++k) {
    Vec3 to(random.uniform(-2, 42), random.uniform(-2, 42), random.uniform(3, 9));
    if (k % 3 == 0) to.z() = at.z();  // level moves: their chords come in closed form
    if (k % 6 == 0) to.y() = at.y();  // along X
    sweeps.emplace_back(bull, at, to, Vec3::UnitZ());
    at = to;
  }
  TriDexel one = TriDexel::from_box(Aabb{{0, 0, 0}, {40, 40, 8}}, 0.3);
  TriDexel batch = one;
  std::vector<TriDexel::Removal> singles;
  std::vector<TriDexel::Cut> cuts;
  for (const LinearSweep& sweep : sweeps) {
    const auto chord = [&sweep](const Ray& ray) { return sweep.chord(ray); };
    singles.push_back(one.remove(sweep.bounds(), chord));
    // The batch takes the chords a row at a time (as the engagement's removal does).
    cuts.push_back(
        {sweep.bounds(),
         chord,
         {},
         [&sweep](const Ray& ray, int across, std::span<const double> along,
                  std::span<Interval> chords) { sweep.chords(ray, across, along, chords); }});
  }
  const std::vector<TriDexel::Removal> batched = batch.remove(cuts);
  ASSERT_EQ(batched.size(), singles.size());
  int cutting = 0;
  for (std::size_t k = 0; k < singles.size(); ++k) {
    EXPECT_EQ(batched[k].rays, singles[k].rays) << k;
    EXPECT_EQ(batched[k].volume, singles[k].volume) << k;
    cutting += singles[k].volume > 0.0 ? 1 : 0;
  }
  EXPECT_GT(cutting, 20);
  for (int a = 0; a < 3; ++a) {
    for (int j = 0; j < one.grid(a)[1]; ++j) {
      for (int i = 0; i < one.grid(a)[0]; ++i) {
        ASSERT_EQ(one.at(a, i, j).intervals(), batch.at(a, i, j).intervals());
      }
    }
  }
  EXPECT_EQ(batch.memory().heap_bytes, batch.count_heap_bytes());
}

// A box whose sides are not whole multiples of the spacing is still represented exactly: its
// cells tile it (each side cut into the fewest cells no wider than s), so its volume and a
// through slot's are exact up to float rounding of the ray ends (1e-7 relative).
TEST(TriDexel, BoxOfAnySizeIsExact) {
  const Aabb box{{0, 0, -30}, {100.0013, 60, 0}};
  TriDexel d = TriDexel::from_box(box, 0.1);
  EXPECT_EQ(d.domain().min, box.min);
  EXPECT_EQ(d.domain().max, box.max);
  EXPECT_EQ(d.grid(1)[1], 1001);  // Y rays across X: 100.0013 / 0.1 rounded up
  EXPECT_NEAR(d.spacing(0), 100.0013 / 1001, 1e-15);
  EXPECT_NEAR(d.spacing(), 0.1, 1e-15);
  const double exact = 100.0013 * 60 * 30;
  for (const double v : d.volume().by_family) EXPECT_NEAR(v, exact, 1e-7 * exact);
  // A 10 mm flat end mill slotting 3 mm deep along X through the whole block.
  const Cutter flat = cutter_from_spec("flat:10,20");
  const LinearSweep slot(flat, {-10, 30, -3}, {110.0013, 30, -3}, Vec3::UnitZ());
  const double removed =
      d.remove(slot.bounds(), [&slot](const Ray& ray) { return slot.chord(ray); }).volume;
  EXPECT_NEAR(removed, 10 * 3 * 100.0013, 1e-7 * exact);
  for (const double v : d.volume().by_family) {
    EXPECT_NEAR(v, exact - 10 * 3 * 100.0013, 1e-7 * exact);
  }
}

// The record of a removal is exactly what the rays lost: ray by ray, the material before less
// the material after, and the same for any order of the tiles (it is sorted).
TEST(TriDexel, RemovalRecordIsWhatTheRaysLost) {
  test::Random random(71);
  const Cutter ball = cutter_from_spec("ball:6,12");
  TriDexel before = TriDexel::from_box(Aabb{{0, 0, 0}, {30, 20, 8}}, 0.25);
  // Earlier cuts leave rays of several intervals.
  for (int k = 0; k < 6; ++k) {
    const LinearSweep sweep(ball, {random.uniform(0, 30), random.uniform(0, 20), 4},
                            {random.uniform(0, 30), random.uniform(0, 20), 6}, Vec3::UnitZ());
    before.remove(sweep.bounds(), [&sweep](const Ray& ray) { return sweep.chord(ray); });
  }
  TriDexel after = before;
  const LinearSweep step(ball, {-4, 10, 3}, {34, 12, 5}, Vec3::UnitZ());
  RemovalRecord record;
  const double volume =
      after
          .remove({{step.bounds(), [&step](const Ray& ray) { return step.chord(ray); }, {}, {}}},
                  &record)
          .front()
          .volume;
  ASSERT_FALSE(record.empty());
  double recorded = 0.0;
  // Rays that lost one stretch and rays that lost several: the record finds the first kind from
  // its rows' masks alone, the second by a search.
  int single = 0, several = 0;
  for (int a = 0; a < 3; ++a) {
    std::size_t in_family = 0;
    for (int j = 0; j < before.grid(a)[1]; ++j) {
      for (int i = 0; i < before.grid(a)[0]; ++i) {
        double taken = 0.0;
        const std::size_t count = record.on_ray(a, i, j).size();
        single += count == 1 ? 1 : 0;
        several += count > 1 ? 1 : 0;
        for (const RemovalRecord::Stretch& s : record.on_ray(a, i, j)) {
          ASSERT_LT(s.lo, s.hi);
          ASSERT_EQ(s.i, i);
          ASSERT_EQ(s.j, j);
          ++in_family;
          // Each stretch was material before and is none after.
          const double mid = 0.5 * (static_cast<double>(s.lo) + s.hi);
          EXPECT_TRUE(before.at(a, i, j).contains(mid));
          EXPECT_FALSE(after.at(a, i, j).contains(mid));
          taken += static_cast<double>(s.hi) - s.lo;
        }
        EXPECT_NEAR(taken, before.at(a, i, j).length() - after.at(a, i, j).length(), 1e-5);
        recorded += taken;
      }
    }
    EXPECT_EQ(in_family, record.family(a).size());
  }
  EXPECT_NEAR(recorded * 0.25 * 0.25 / 3.0, volume, 1e-6 * volume);
  EXPECT_GT(volume, 100.0);
  EXPECT_GT(single, 0);
  EXPECT_GT(several, 0);
}

// The chord of a ray through the region {p : lo ≤ n·p ≤ hi for each (n, lo, hi)}.
struct Slab {
  Vec3 n;
  double lo, hi;
};
Interval slab_chord(const Ray& ray, const std::vector<Slab>& slabs) {
  Interval chord{-1e9, 1e9};
  for (const Slab& slab : slabs) {
    const double at = slab.n.dot(ray.origin), rate = slab.n.dot(ray.direction);
    if (rate == 0.0) {
      if (at < slab.lo || at > slab.hi) return Interval::empty();
      continue;
    }
    const double t0 = (slab.lo - at) / rate, t1 = (slab.hi - at) / rate;
    chord = {std::max(chord.lo, std::min(t0, t1)), std::min(chord.hi, std::max(t0, t1))};
  }
  return chord.lo < chord.hi ? chord : Interval::empty();
}

// RemovalRecord::alike against every ray's stretches compared one by one. A flat end mill's
// level step takes alike from height to height down its side, and an earlier slot at another
// depth makes some heights differ. Two slanted cuts recorded with it take, at each height, what
// the height below took on the next ray over (a slab leaning at 45° across rays 0.25 mm apart),
// and stretches that start alike and end apart (a block whose end slants in Y and Z). Every pair
// of indices across every family is compared, both ways (rows: j, and columns: i), over tiles of
// 32 rays.
TEST(TriDexel, RecordRowsAreAlikeWhereEveryRayLostTheSame) {
  const Cutter flat = cutter_from_spec("flat:6,12");
  TriDexel stock = TriDexel::from_box(Aabb{{0, 0, 0}, {30, 20, 8}}, 0.25);
  const LinearSweep earlier(flat, {-5, 12, 6}, {35, 12, 6}, Vec3::UnitZ());
  stock.remove(earlier.bounds(), [&earlier](const Ray& ray) { return earlier.chord(ray); });
  const LinearSweep step(flat, {8, 10, 3}, {12, 10, 3}, Vec3::UnitZ());
  const double inf = 1e9;
  const std::vector<Slab> leaning{
      {Vec3::UnitX(), 20.1, 22.1}, {Vec3(0, 1, -1), 1.1, 2.1}, {Vec3::UnitZ(), 1.0, 3.0}};
  const std::vector<Slab> slanted{{Vec3::UnitX(), 24.1, inf},
                                  {Vec3(1, -0.5, -0.5), -inf, 17.35},
                                  {Vec3::UnitY(), 15.1, 16.1},
                                  {Vec3::UnitZ(), 4.0, 5.5}};
  const auto region = [](const std::vector<Slab>& slabs) {
    Aabb box;
    box.min = Vec3(0, 0, 0);
    box.max = Vec3(30, 20, 8);
    return TriDexel::Cut{box, [&slabs](const Ray& ray) { return slab_chord(ray, slabs); }, {}, {}};
  };
  RemovalRecord record;
  stock.remove({{step.bounds(), [&step](const Ray& ray) { return step.chord(ray); }, {}, {}},
                region(leaning),
                region(slanted)},
               &record);
  ASSERT_FALSE(record.empty());
  int alike = 0, unlike = 0;
  for (int a = 0; a < 3; ++a) {
    const std::array<int, 2> grid = stock.grid(a);
    for (int across = 0; across < 2; ++across) {
      const int n = grid[static_cast<std::size_t>(across)];
      const int m = grid[static_cast<std::size_t>(1 - across)];
      // Whether index p's rays lost what index q's did, ray by ray.
      const auto same = [&](int p, int q) {
        for (int o = 0; o < m; ++o) {
          const auto x = across == 0 ? record.on_ray(a, p, o) : record.on_ray(a, o, p);
          const auto y = across == 0 ? record.on_ray(a, q, o) : record.on_ray(a, o, q);
          if (x.size() != y.size()) return false;
          for (std::size_t k = 0; k < x.size(); ++k) {
            if (x[k].lo != y[k].lo || x[k].hi != y[k].hi) return false;
          }
        }
        return true;
      };
      for (int p = 0; p < n; ++p) {
        for (int q = 0; q < n; ++q) {
          const bool expected = same(p, q);
          ASSERT_EQ(record.alike(a, across, p, q), expected)
              << "family " << a << (across == 0 ? " i " : " j ") << p << " and " << q;
          if (p != q) (expected ? alike : unlike) += 1;
        }
      }
    }
  }
  EXPECT_GT(alike, 1000);
  EXPECT_GT(unlike, 1000);
}

// A cut's rows of one key (Cut::row_key: a level sweep's rows of X rays at heights of one tool
// radius) share their chords only where they hold the same rays: a slab leaning at 45° across
// the X rays emptied a run of rays that moves over by one ray from row to row, so the rows up
// the flat end mill's side each hold as many rays but not the same. Every ray ends as cutting it
// by the sweep's own chord leaves it.
TEST(TriDexel, RowsOfOneKeyShareChordsOnlyOverTheSameRays) {
  const Cutter flat = cutter_from_spec("flat:6,12");
  TriDexel rows = TriDexel::from_box(Aabb{{0, 0, 0}, {30, 20, 8}}, 0.25);
  const std::vector<Slab> leaning{{Vec3(0, 1, -1), 4.1, 5.1}, {Vec3::UnitZ(), 2.0, 7.0}};
  rows.remove(rows.domain(), [&leaning](const Ray& ray) { return slab_chord(ray, leaning); });
  TriDexel each = rows;
  const LinearSweep step(flat, {8, 8, 2.5}, {20, 8, 2.5}, Vec3::UnitZ());
  TriDexel::Cut cut{step.bounds(), [&step](const Ray& ray) { return step.chord(ray); }, {}, {}};
  cut.rows = [&step](const Ray& ray, int across, std::span<const double> at,
                     std::span<Interval> chords) { step.chords(ray, across, at, chords); };
  cut.row_key = [&step](const Ray& ray, int across) { return step.row_key(ray, across); };
  const double volume = rows.remove({cut}).front().volume;
  each.remove(step.bounds(), [&step](const Ray& ray) { return step.chord(ray); });
  EXPECT_GT(volume, 100.0);
  for (int a = 0; a < 3; ++a) {
    for (int j = 0; j < rows.grid(a)[1]; ++j) {
      for (int i = 0; i < rows.grid(a)[0]; ++i) {
        ASSERT_EQ(rows.at(a, i, j).intervals(), each.at(a, i, j).intervals())
            << "family " << a << " ray " << i << ", " << j;
      }
    }
  }
}

// Removal skips a tile row of rays whose material it found clear of an earlier cut's box when
// the next box lies in that clear stretch. A pocket cleared in 0.5 mm steps, each removed on its
// own with its record (as the engagement's removal does), at two levels joined by plunges, ends
// with every ray as cutting each ray by every step's chord gives it, and each step's record is
// what that ray lost: skipping changes nothing.
TEST(TriDexel, SkippingClearRowsChangesNoRay) {
  const Cutter flat = cutter_from_spec("flat:6,12");
  std::vector<LinearSweep> steps;
  Vec3 at(3, 3, 8);
  const auto go = [&](const Vec3& to) {
    if (to == at) return;
    const int n = std::max(1, static_cast<int>(std::ceil((to - at).norm() / 0.5)));
    for (int k = 1; k <= n; ++k) {
      const Vec3 next = at + (to - at) * (static_cast<double>(k) / n);
      steps.emplace_back(flat, k == 1 ? at : steps.back().end(), next, Vec3::UnitZ());
    }
    at = to;
  };
  for (const double z : {8.0, 6.0}) {
    go({3, 3, z});
    for (int row = 0; row < 4; ++row) {
      const double y = 3.0 + 3.0 * row;
      go({at.x(), y, z});
      go({row % 2 == 0 ? 21.0 : 3.0, y, z});
    }
    go({3, 3, z});
  }
  TriDexel stock = TriDexel::from_box(Aabb{{0, 0, 0}, {24, 16, 10}}, 0.25);
  // The same steps as one batch (each tile applies them in turn, tiles in parallel): a span one
  // step notes is used by the next within the pass.
  TriDexel batched = stock;
  {
    std::vector<TriDexel::Cut> cuts;
    for (const LinearSweep& step : steps) {
      cuts.push_back({step.bounds(), [&step](const Ray& ray) { return step.chord(ray); }, {}, {}});
    }
    batched.remove(cuts);
  }
  std::array<std::vector<DexelRay>, 3> reference;  // the rays, cut one by one
  for (int a = 0; a < 3; ++a) {
    for (int j = 0; j < stock.grid(a)[1]; ++j) {
      for (int i = 0; i < stock.grid(a)[0]; ++i) reference[a].push_back(stock.at(a, i, j));
    }
  }
  RemovalRecord record;
  std::vector<Interval> lost;
  for (const LinearSweep& step : steps) {
    stock.remove(
        {{step.bounds(),
          [&step](const Ray& ray) { return step.chord(ray); },
          {},
          [&step](const Ray& ray, int across, std::span<const double> along,
                  std::span<Interval> chords) { step.chords(ray, across, along, chords); }}},
        &record);
    const Aabb box = step.bounds();
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      std::size_t stretches = 0;
      for (int j = 0; j < stock.grid(a)[1]; ++j) {
        for (int i = 0; i < stock.grid(a)[0]; ++i) {
          const Ray ray = stock.ray(a, i, j);
          if (ray.origin[b] < box.min[b] || ray.origin[b] > box.max[b] ||
              ray.origin[c] < box.min[c] || ray.origin[c] > box.max[c]) {
            continue;
          }
          const Interval chord = step.chord(ray);
          if (chord.is_empty()) continue;
          DexelRay& material = reference[a][static_cast<std::size_t>(j * stock.grid(a)[0] + i)];
          lost.clear();
          material.subtract(chord.lo, chord.hi, &lost);
          const std::span<const RemovalRecord::Stretch> recorded = record.on_ray(a, i, j);
          ASSERT_EQ(recorded.size(), lost.size()) << a << " " << i << " " << j;
          for (std::size_t k = 0; k < lost.size(); ++k) {
            ASSERT_EQ(recorded[k].lo, static_cast<float>(lost[k].lo));
            ASSERT_EQ(recorded[k].hi, static_cast<float>(lost[k].hi));
          }
          stretches += lost.size();
        }
      }
      ASSERT_EQ(record.family(a).size(), stretches);
    }
  }
  for (int a = 0; a < 3; ++a) {
    for (int j = 0; j < stock.grid(a)[1]; ++j) {
      for (int i = 0; i < stock.grid(a)[0]; ++i) {
        const auto expected =
            reference[a][static_cast<std::size_t>(j * stock.grid(a)[0] + i)].intervals();
        ASSERT_EQ(stock.at(a, i, j).intervals(), expected);
        ASSERT_EQ(batched.at(a, i, j).intervals(), expected);
      }
    }
  }
  // Rows were found clear and skipped; 3 + 4·18·2 + 3 steps of 0.5 mm per level at least.
  EXPECT_GT(stock.free_rows(), 100u);
  EXPECT_GT(batched.free_rows(), 100u);
  EXPECT_GT(steps.size(), 300u);
  // The pocket: the 18 × 9 mm rectangle of the tool's centres grown by its 3 mm radius, 4 mm
  // deep; the families' mean within a third of perimeter × depth × spacing.
  const double removed = 4.0 * (18.0 * 9.0 + 2.0 * 3.0 * (18.0 + 9.0) + kPi * 9.0);
  const double perimeter = 2.0 * (18.0 + 9.0) + 2.0 * kPi * 3.0;
  EXPECT_NEAR(stock.volume().mean(), 24.0 * 16.0 * 10.0 - removed, perimeter * 4.0 * 0.25 / 3.0);
}

}  // namespace
}  // namespace cwe

namespace cwe {
namespace {

double removed_by(TriDexel& d, const Cutter& cutter, const Vec3& from, const Vec3& to, int family) {
  const double before = d.volume().by_family[static_cast<std::size_t>(family)];
  const LinearSweep sweep(cutter, from, to, Vec3::UnitZ());
  d.remove(sweep.bounds(), [&sweep](const Ray& ray) { return sweep.chord(ray); });
  return before - d.volume().by_family[static_cast<std::size_t>(family)];
}

// A flat end mill slotting straight through a 40 × 20 × 10 block, 3 mm deep: 10 × 40 × 3 mm³.
// The slot's faces fall between ray centres, so every family measures it exactly (float
// rounding of 1e-5 mm per ray end).
TEST(TriDexelRemoval, StraightSlotIsExact) {
  TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {40, 20, 10}}, 0.1);
  const double before = d.volume().mean();
  const Cutter flat = cutter_from_spec("flat:10,20");
  const LinearSweep sweep(flat, Vec3(-10, 10, 7), Vec3(50, 10, 7), Vec3::UnitZ());
  d.remove(sweep.bounds(), [&sweep](const Ray& ray) { return sweep.chord(ray); });
  const TriDexel::Volume after = d.volume();
  for (const double v : after.by_family) EXPECT_NEAR(before - v, 1200.0, 0.05);
}

// A ball end mill grooving 3 mm deep: the cross-section is a circular segment,
// r² acos((r - h)/r) - (r - h)√(2rh - h²), times the 40 mm length. Rays along the groove carry
// exact lengths; their count samples the segment's area with at most (perimeter/s + 4) cells in
// error, each s² × 40 mm³.
TEST(TriDexelRemoval, BallGrooveMatchesTheCircularSegment) {
  TriDexel d = TriDexel::from_box(Aabb{{0, 0, 0}, {40, 20, 10}}, 0.1);
  const double r = 5.0, h = 3.0;
  const double area = r * r * std::acos((r - h) / r) - (r - h) * std::sqrt(2 * r * h - h * h);
  const double perimeter = 2 * r * std::acos((r - h) / r) + 2 * std::sqrt(2 * r * h - h * h);
  const double bound = (perimeter / 0.1 + 4) * 0.01 * 40.0;
  const double removed =
      removed_by(d, cutter_from_spec("ball:10,20"), Vec3(-10, 10.02, 7), Vec3(50, 10.02, 7), 0);
  EXPECT_NEAR(removed, area * 40.0, bound);
  // Every family agrees within its own sampling error; the spread shows it.
  EXPECT_LT(d.volume().spread(), 2 * bound);
}

// Checks that `got` holds what `want` holds, stretch for stretch, and that the look-up engagement
// makes finds each ray's stretches and nothing on the rays without, over `box` (a step's) grown
// by a tile (tiles a group's other steps reached, whose records are reused). The stretches.
std::size_t same_record(const RemovalRecord& got, const RemovalRecord& want, const Aabb& box,
                        const TriDexel& grid) {
  EXPECT_EQ(got.bounds().min, want.bounds().min);
  EXPECT_EQ(got.bounds().max, want.bounds().max);
  std::size_t stretches = 0;
  for (int a = 0; a < 3; ++a) {
    const std::vector<RemovalRecord::Stretch> mine = got.family(a), theirs = want.family(a);
    EXPECT_EQ(mine.size(), theirs.size()) << a;
    if (mine.size() != theirs.size()) return 0;
    std::map<std::pair<int, int>, std::vector<std::pair<float, float>>> by_ray;
    for (std::size_t n = 0; n < mine.size(); ++n) {
      EXPECT_EQ(mine[n].i, theirs[n].i);
      EXPECT_EQ(mine[n].j, theirs[n].j);
      EXPECT_EQ(mine[n].lo, theirs[n].lo);
      EXPECT_EQ(mine[n].hi, theirs[n].hi);
      by_ray[{mine[n].i, mine[n].j}].emplace_back(mine[n].lo, mine[n].hi);
    }
    stretches += mine.size();
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double s = grid.spacing(), grow = (TriDexel::kTile + 1) * s;
    const int first_i = std::max(0, static_cast<int>((box.min[b] - grow) / s));
    const int first_j = std::max(0, static_cast<int>((box.min[c] - grow) / s));
    const int last_i = std::min(grid.grid(a)[0] - 1, static_cast<int>((box.max[b] + grow) / s));
    const int last_j = std::min(grid.grid(a)[1] - 1, static_cast<int>((box.max[c] + grow) / s));
    for (int j = first_j; j <= last_j; ++j) {
      for (int i = first_i; i <= last_i; ++i) {
        std::vector<std::pair<float, float>> on;
        for (const RemovalRecord::Stretch& x : got.on_ray(a, i, j)) on.emplace_back(x.lo, x.hi);
        const auto it = by_ray.find({i, j});
        EXPECT_EQ(on, it == by_ray.end() ? decltype(on){} : it->second)
            << a << " " << i << " " << j;
        if (::testing::Test::HasFailure()) return 0;
      }
    }
  }
  return stretches;
}

// Steps removed a group at a time, each into its own record (the main loop's groups), give every
// ray, record and removal that one call per step gives: with groups of every size, steps without
// a record among them, and a record holding two cuts; and records indexed later (as the main
// loop has them indexed beside their engagement) hold what records indexed at once hold.
TEST(TriDexel, RecordsPerCutMatchOneCallPerStep) {
  const Cutter ball = cutter_from_spec("ball:5,12");
  std::vector<LinearSweep> steps;
  Vec3 at(2, 2, 9);
  const auto go = [&](const Vec3& to) {
    const int n = std::max(1, static_cast<int>(std::ceil((to - at).norm() / 0.5)));
    for (int k = 1; k <= n; ++k) {
      const Vec3 next = at + (to - at) * (static_cast<double>(k) / n);
      steps.emplace_back(ball, k == 1 ? at : steps.back().end(), next, Vec3::UnitZ());
    }
    at = to;
  };
  // A ramp down across the block, rows back and forth, then a plunge through a row: material
  // left in several pieces on some rays.
  go({22, 8, 6});
  for (int row = 0; row < 3; ++row) {
    go({at.x(), 3.0 + 5.0 * row, 6});
    go({row % 2 == 0 ? 2.0 : 22.0, at.y(), 6});
  }
  go({12, 8, 6});
  go({12, 8, 2});
  go({12, 14, 4});
  const auto cut_of = [](const LinearSweep& step) {
    return TriDexel::Cut{
        step.bounds(),
        [&step](const Ray& ray) { return step.chord(ray); },
        {},
        [&step](const Ray& ray, int across, std::span<const double> along,
                std::span<Interval> chords) { step.chords(ray, across, along, chords); }};
  };
  // Every third step is motion without a record; a step at 7 mod 10 shares its record with the
  // step after it (one record of two cuts).
  const auto recorded = [](std::size_t k) { return k % 3 != 2; };
  const auto shares_next = [&](std::size_t k) {
    return k % 10 == 7 && k + 1 < steps.size() && recorded(k) && recorded(k + 1);
  };
  // 0.1 mm rays: a group reaches more tiles than the serial bound, so it runs in parallel.
  const TriDexel start = TriDexel::from_box(Aabb{{0, 0, 0}, {24, 17, 10}}, 0.1);
  TriDexel one_by_one = start;
  std::vector<RemovalRecord> expected(steps.size());
  std::vector<TriDexel::Removal> expected_removals;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    std::vector<TriDexel::Cut> cuts{cut_of(steps[k])};
    if (shares_next(k)) cuts.push_back(cut_of(steps[k + 1]));
    const std::vector<TriDexel::Removal> removed =
        one_by_one.remove(cuts, recorded(k) ? &expected[k] : nullptr);
    expected_removals.insert(expected_removals.end(), removed.begin(), removed.end());
    if (shares_next(k)) ++k;
  }
  ASSERT_GT(steps.size(), 150u);
  const std::pair<std::size_t, TriDexel::Indexing> groups[] = {
      {1, TriDexel::Indexing::kNow},      {5, TriDexel::Indexing::kNow},
      {16, TriDexel::Indexing::kNow},     {37, TriDexel::Indexing::kNow},
      {5, TriDexel::Indexing::kDeferred}, {37, TriDexel::Indexing::kDeferred}};
  for (const auto& [group, indexing] : groups) {
    SCOPED_TRACE(group);
    SCOPED_TRACE(indexing == TriDexel::Indexing::kNow ? "indexed at once" : "indexed later");
    TriDexel grouped = start;
    // The records are reused group after group, as the main loop reuses them.
    std::vector<RemovalRecord> pool(group);
    std::vector<TriDexel::Removal> removals;
    std::size_t stretches = 0;
    for (std::size_t first = 0; first < steps.size();) {
      std::vector<TriDexel::Cut> cuts;
      std::vector<RemovalRecord*> owners;
      std::vector<std::pair<std::size_t, RemovalRecord*>> checks;  // step, its record
      std::size_t k = first;
      for (std::size_t n = 0; n < group && k < steps.size(); ++n, ++k) {
        cuts.push_back(cut_of(steps[k]));
        owners.push_back(recorded(k) ? &pool[n] : nullptr);
        if (recorded(k)) checks.emplace_back(k, &pool[n]);
        if (shares_next(k)) {
          cuts.push_back(cut_of(steps[++k]));
          owners.push_back(&pool[n]);
        }
      }
      first = k;
      // Now and then a record gives its buffers back (as the main loop's do after a large
      // step): it must fill as well from nothing.
      if (k % 7 == 0 && pool[0].held_bytes() > 0) {
        pool[0].release();
        EXPECT_EQ(pool[0].held_bytes(), 0u);
      }
      const std::vector<TriDexel::Removal> removed = grouped.remove(cuts, owners, indexing);
      removals.insert(removals.end(), removed.begin(), removed.end());
      for (const auto& [step, record] : checks) {
        EXPECT_EQ(record->indexed(), indexing == TriDexel::Indexing::kNow);
        record->index();
        ASSERT_TRUE(record->indexed());
        stretches += same_record(*record, expected[step], steps[step].bounds(), start);
      }
    }
    ASSERT_EQ(removals.size(), expected_removals.size());
    for (std::size_t k = 0; k < removals.size(); ++k) {
      ASSERT_EQ(removals[k].rays, expected_removals[k].rays) << k;
      ASSERT_EQ(removals[k].volume, expected_removals[k].volume) << k;
    }
    EXPECT_GT(stretches, 10000u);
    for (int a = 0; a < 3; ++a) {
      for (int j = 0; j < start.grid(a)[1]; ++j) {
        for (int i = 0; i < start.grid(a)[0]; ++i) {
          ASSERT_EQ(grouped.at(a, i, j).intervals(), one_by_one.at(a, i, j).intervals());
        }
      }
    }
  }
}

}  // namespace
}  // namespace cwe
