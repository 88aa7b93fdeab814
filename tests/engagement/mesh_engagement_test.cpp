// The polyhedral workpiece (MeshStock, MeshWorkpiece): exact volumes of booleans, refusal of open
// stock, the removed volume of a slot against the closed form of its faceted sweep, and the
// engagement of slotting, up- and down-milling and a plunge against the closed forms
// (docs/engagement.md, "Method (mesh workpiece)").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/engagement/mesh_workpiece.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/workpiece/mesh/mesh_stock.hpp"
#include "engagement_testing.hpp"

namespace cwe {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kSpacing = 0.1;  // the grid's disc height and cell size
constexpr double kFacet = 1.0;    // mm, the tool's ring edges at its largest radius

TriangleMesh box_mesh(const Aabb& box) { return MeshStock::from_box(box).mesh(); }

TEST(MeshStock, BoxMinusBoxIsExact) {
  MeshStock stock = MeshStock::from_box({{0, 0, 0}, {10, 10, 10}});
  EXPECT_NEAR(stock.volume(), 1000.0, 1e-9);
  TriangleMesh removed;
  // A corner of 2 × 3 × 4 inside the stock and the rest of the tool outside it.
  EXPECT_NEAR(stock.subtract(box_mesh({{8, 7, 6}, {12, 12, 12}}), &removed), 24.0, 1e-9);
  EXPECT_NEAR(stock.volume(), 976.0, 1e-9);
  EXPECT_NEAR(removed.volume(), 24.0, 1e-9);
  EXPECT_TRUE(check_closure(removed).closed());
  EXPECT_TRUE(check_closure(stock.mesh()).closed());
  // The same tool again removes nothing; a tool far away is not even looked at.
  EXPECT_NEAR(stock.subtract(box_mesh({{8, 7, 6}, {12, 12, 12}})), 0.0, 1e-9);
  EXPECT_EQ(stock.subtract(box_mesh({{20, 20, 20}, {21, 21, 21}})), 0.0);
  // A tool through the whole stock splits it: two closed shells, their volumes summed.
  EXPECT_NEAR(stock.subtract(box_mesh({{4, -1, -1}, {5, 11, 11}})), 100.0, 1e-9);
  EXPECT_NEAR(stock.volume(), 876.0, 1e-9);
}

// The number of connected shells of `mesh` (triangles joined through shared vertices).
int shells(const TriangleMesh& mesh) {
  std::vector<int> parent(mesh.vertices.size());
  for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = static_cast<int>(k);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) v = parent[static_cast<std::size_t>(v)];
    return v;
  };
  for (const auto& t : mesh.triangles) {
    parent[static_cast<std::size_t>(root(t[1]))] = root(t[0]);
    parent[static_cast<std::size_t>(root(t[2]))] = root(t[0]);
  }
  std::set<int> roots;
  for (const auto& t : mesh.triangles) roots.insert(root(t[0]));
  return static_cast<int>(roots.size());
}

// A move's pieces are subtracted as one solid: their union. Overlapping pieces (an arc's,
// which share the tool at each joint) remove their union's volume once, and what they removed
// is one closed solid; pieces that only touch along an edge have no 2-manifold union and are
// subtracted one by one, with the same result.
TEST(MeshStock, SubtractsAMovesPiecesAsTheirUnion) {
  MeshStock stock = MeshStock::from_box({{0, 0, 0}, {10, 10, 10}});
  // Three boxes along x, each overlapping the next by 1 mm, 2 × 2 in y, z around the stock's
  // top corner: inside the stock x ∈ [1, 8], y ∈ [8, 10], z ∈ [9, 10]; 7 · 2 · 1 = 14 mm³.
  const std::vector<TriangleMesh> chain = {box_mesh({{1, 8, 9}, {4, 12, 12}}),
                                           box_mesh({{3, 8, 9}, {6, 12, 12}}),
                                           box_mesh({{5, 8, 9}, {8, 12, 12}})};
  TriangleMesh removed;
  EXPECT_NEAR(stock.subtract(chain, &removed), 14.0, 1e-9);
  EXPECT_NEAR(stock.volume(), 986.0, 1e-9);
  EXPECT_NEAR(removed.volume(), 14.0, 1e-9);
  EXPECT_TRUE(check_closure(removed).closed());
  EXPECT_TRUE(check_closure(stock.mesh()).closed());
  EXPECT_EQ(shells(removed), 1);  // one solid, not three stacked
  // Two pieces touching along an edge below the stock (x = 2, y = −2): no 2-manifold union, so
  // each is taken on its own. A box, and a prism whose section is the triangle (2, −2), (5, −2),
  // (5, 1): inside the stock, 2 × 1 × 1 and the triangle x ∈ [4, 5], 0 ≤ y ≤ x − 4, 1 deep.
  std::vector<Vec3> corners;
  for (const double z : {-1.0, 1.0}) {
    for (const Vec2& p : {Vec2(2, -2), Vec2(5, -2), Vec2(5, 1)})
      corners.emplace_back(p.x(), p.y(), z);
  }
  const std::vector<TriangleMesh> touching = {box_mesh({{0, -2, -1}, {2, 1, 1}}),
                                              convex_hull(corners)};
  removed = TriangleMesh();
  EXPECT_NEAR(stock.subtract(touching, &removed), 2.5, 1e-9);
  EXPECT_NEAR(stock.volume(), 983.5, 1e-9);
  EXPECT_NEAR(removed.volume(), 2.5, 1e-9);
  EXPECT_EQ(shells(removed), 2);
  EXPECT_TRUE(check_closure(stock.mesh()).closed());
  // Pieces away from the stock are not looked at; no pieces, nothing removed.
  EXPECT_EQ(stock.subtract(std::vector<TriangleMesh>{box_mesh({{20, 20, 20}, {21, 21, 21}})}), 0.0);
  EXPECT_EQ(stock.subtract(std::vector<TriangleMesh>{}), 0.0);
}

// A removed volume that touches itself along an edge has no 2-manifold mesh: the stock's top is
// 1 mm above the cut for x < 5, steps down to it at x = 5 and ramps back up by x = 10 (a helix
// ending where a circle then cleans the floor). The stock still loses exactly that volume, and
// the RV comes back as a closed solid grown by a relative 1e-9 (its volume within 1e-6).
TEST(MeshStock, PinchedRemovalVolumeIsGrownByAHair) {
  MeshStock stock = MeshStock::from_box({{0, 0, 0}, {10, 10, 6}});
  std::vector<Vec3> wedge;
  for (const double y : {-1.0, 11.0}) {
    for (const Vec2& p : {Vec2(5, 5), Vec2(10, 6), Vec2(10, 7), Vec2(5, 7)}) {
      wedge.emplace_back(p.x(), y, p.y());
    }
  }
  EXPECT_NEAR(stock.subtract(convex_hull(wedge)), 25.0, 1e-9);  // ½ · 5 · 1 · 10
  TriangleMesh removed;
  // Above z = 5: 5 × 10 × 1 for x < 5 and the ramp's 25.
  EXPECT_NEAR(stock.subtract(box_mesh({{-1, -1, 5}, {11, 11, 8}}), &removed), 75.0, 1e-9);
  EXPECT_NEAR(stock.volume(), 500.0, 1e-9);
  EXPECT_TRUE(check_closure(removed).closed());
  EXPECT_NEAR(removed.volume(), 75.0, 75.0 * 1e-6);
}

TEST(MeshStock, RefusesWhatIsNotASolid) {
  TriangleMesh open = box_mesh({{0, 0, 0}, {1, 1, 1}});
  open.triangles.pop_back();
  try {
    MeshStock::from_mesh(open, "part.stl");
    FAIL() << "an open surface was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, "part.stl");
    EXPECT_NE(e.message().find("not closed"), std::string::npos) << e.what();
  }
  TriangleMesh inside_out = box_mesh({{0, 0, 0}, {1, 1, 1}});
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  EXPECT_THROW(MeshStock::from_mesh(inside_out, "part.stl"), InputError);
  // Two boxes overlapping: a closed surface that crosses itself.
  TriangleMesh crossing = box_mesh({{0, 0, 0}, {2, 2, 2}});
  crossing.append(box_mesh({{1, 1, 1}, {3, 3, 3}}));
  EXPECT_THROW(MeshStock::from_mesh(crossing, "part.stl"), InputError);
  EXPECT_THROW(MeshStock::from_box({{0, 0, 0}, {1, 0, 1}}), InputError);
}

using test::line;

// The sides of a ring of radius ρ of the faceted tool (tool_surface_points' count for chord
// depth h): at the largest radius, chords of the facet size.
int ring_sides(double rho, double h) {
  if (rho <= h) return 8;  // a ring within its chords' depth of the axis: the fewest sides
  return std::max(8, static_cast<int>(std::ceil(kPi / std::acos(1.0 - h / rho))));
}

// A flat end mill D = 10, 3 mm deep, from outside the block (x < 0) to x = 50 along y = 20: the
// faceted tool's ring is a regular polygon with a vertex on the feed's left (+y), so its sweep
// is a slab 2R wide (an even number of sides) ending in the polygon's front half.
TEST(MeshWorkpiece, SlotRemovesTheFacetedSweep) {
  const double r = 5.0, depth = 3.0;
  const Cutter cutter = cutter_from_spec("flat:10,20");
  const int n = ring_sides(r, MeshWorkpiece::facet_depth(cutter, kFacet));
  ASSERT_EQ(n, 32);  // chords of 1 mm: ⌈π / asin(0.1)⌉
  MeshStock stock = MeshStock::from_box({{0, 0, 0}, {60, 40, 20}});
  MeshWorkpiece workpiece(stock, kFacet, kSpacing);
  Toolpath path;
  path.sources = {"test"};
  path.moves = {line({-10, 20, 20 - depth}, {50, 20, 20 - depth})};
  const RemovalSummary summary = remove_toolpath(workpiece, cutter, path, {kSpacing, 0.0});
  const double front = 0.25 * n * r * r * std::sin(2 * kPi / n);
  const double expected = depth * (2 * r * 50.0 + front);
  ASSERT_EQ(summary.removed_by_move.size(), 1u);
  EXPECT_NEAR(summary.removed_by_move[0], expected, 1e-9 * expected);
  EXPECT_NEAR(stock.volume(), 60.0 * 40.0 * 20.0 - expected, 1e-9 * expected);
  EXPECT_TRUE(check_closure(stock.mesh()).closed());
  // Against the true sweep (a half disc in front): the facets are inside it.
  EXPECT_LT(expected, depth * (2 * r * 50.0 + 0.5 * kPi * r * r));
}

// A planar arc is swept from the tool's section revolved (planar_arc_sweep): solids CGAL
// accepts (closed, outward, not crossing themselves) for every kind of tool, one mesh or, around
// a corner (R ≤ r), three; and what the one mesh removes from a block against the closed form
// for a flat end mill, (sweep·2R·r + πr²)·depth: its vertices lie on the true surface, so it
// differs by at most its area times the ring chords' depth h plus the stations' sagitta (the
// simulation's tolerance/2).
TEST(MeshWorkpiece, PlanarArcIsSweptInOneOrThreeSolids) {
  Move arc;
  arc.shape = MoveShape::kArc;
  arc.feed_rate = 600.0;
  arc.normal = -Vec3::UnitZ();  // G2
  arc.center = Vec3(30, 20, 17);
  arc.sweep = kPi / 2;
  for (const double big_r : {12.0, 5.0, 3.0}) {
    arc.start = arc.center + big_r * Vec3(std::cos(0.3), std::sin(0.3), 0.0);
    arc.end = arc.position(1.0);
    for (const char* spec : {"flat:10,20", "ball:6,15", "bull:10,2,20", "chamfer:12,90,15"}) {
      SCOPED_TRACE(testing::Message() << spec << ", R " << big_r);
      const Cutter cutter = cutter_from_spec(spec);
      const std::vector<TriangleMesh> meshes =
          planar_arc_sweep(cutter, 2.0 * MeshWorkpiece::facet_depth(cutter, kFacet), 0.01, arc);
      EXPECT_EQ(meshes.size(), big_r > cutter.profile().max_radius() + 0.1 ? 1u : 3u);
      for (const TriangleMesh& mesh : meshes) EXPECT_NO_THROW(MeshStock::from_mesh(mesh, spec));
    }
  }
  arc.start = arc.center + 12.0 * Vec3(std::cos(0.3), std::sin(0.3), 0.0);
  arc.end = arc.position(1.0);
  const double r = 5.0, big_r = 12.0, depth = 3.0;
  const Cutter flat = cutter_from_spec("flat:10,20");
  MeshStock stock = MeshStock::from_box({{0, -10, 0}, {60, 50, 20}});
  MeshWorkpiece workpiece(stock, kFacet, kSpacing);
  Toolpath path;
  path.sources = {"test"};
  path.moves = {arc};
  const RemovalSummary summary = remove_toolpath(workpiece, flat, path, {kSpacing, 0.0});
  const double section = arc.sweep * 2.0 * big_r * r + kPi * r * r;
  const double area = 2.0 * section + depth * (arc.sweep * 2.0 * big_r + kTwoPi * r);
  const double bound = area * (MeshWorkpiece::facet_depth(flat, kFacet) + kSpacing / 20.0);
  ASSERT_EQ(summary.removed_by_move.size(), 1u);
  EXPECT_NEAR(summary.removed_by_move[0], section * depth, bound);
  EXPECT_TRUE(check_closure(stock.mesh()).closed());
}

// The map at the CL sample nearest `probe` of `moves` cut through `block` on the mesh workpiece
// (arcs, helices and 5-axis moves subdivided within `subdivision`, 0: s/10).
EngagementMap mesh_engagement_near(const char* tool, const Aabb& block,
                                   const std::vector<Move>& moves, const Vec3& probe,
                                   double facet = kFacet, double subdivision = 0.0,
                                   int on_move = -1) {
  MeshStock stock = MeshStock::from_box(block);
  MeshWorkpiece workpiece(stock, facet, kSpacing);
  Toolpath path;
  path.sources = {"test"};
  path.moves = moves;
  const Cutter cutter = cutter_from_spec(tool);
  SamplingOptions sampling;
  sampling.step = 0.5;
  EngagementMap best;
  double nearest = 1e300;
  simulate_engagement(workpiece, cutter, path, {{kSpacing, subdivision}, sampling, {}},
                      [&](const ClEngagement& e) {
                        if (on_move >= 0 && e.cl.move != on_move) return;
                        const double d = (e.cl.position - probe).norm();
                        if (d < nearest) {
                          nearest = d;
                          best = e.map;
                        }
                      });
  EXPECT_LT(nearest, 0.5);
  return best;
}

// The angular tolerance the issue asks at 1 mm facets: 1°. What it covers at R = 5: the facets
// lie inside the circle by up to h = 0.025 mm, and a cell counts as touching within h plus the
// contact tolerance (0.01 mm), which moves a boundary where a block face crosses the circle at
// angle α by (2h + contact)/(R sin α) ≈ 0.7° at 60°, plus the bisection's cell/64.
constexpr double kAngle = 1.0 * kDeg;
constexpr double kTop = 20.0;
const std::vector<Move> kPass{line({-10, 20, kTop - 3}, {50, 20, kTop - 3})};
const Vec3 kSteady(25, 20, kTop - 3);

TEST(MeshEngagement, FullSlot) {
  const EngagementMap map =
      mesh_engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}}, kPass, kSteady);
  ASSERT_TRUE(map.engaged);
  test::expect_discs(map, 0.0, 2.9, 0.0, kPi, kAngle);
  EXPECT_NEAR(map.axial_depth, 3.0, kSpacing);
  for (const RingEngagement& ring : map.rings) EXPECT_TRUE(ring.phi.empty());
  EXPECT_NEAR(map.area, kPi * 5.0 * 3.0, 0.02 * kPi * 5.0 * 3.0);
}

TEST(MeshEngagement, UpAndDownMillingAndHalfImmersion) {
  const double r = 5.0;
  for (const double ae : {2.5, 5.0}) {
    SCOPED_TRACE(testing::Message() << "ae " << ae);
    const double edge = 20.0 + r - ae;
    const EngagementMap up =
        mesh_engagement_near("flat:10,20", {{0, edge, 0}, {60, 40, kTop}}, kPass, kSteady);
    test::expect_discs(up, 0.0, 2.9, 0.0, std::acos(1.0 - ae / r), kAngle);
    EXPECT_NEAR(up.axial_depth, 3.0, kSpacing);
    const EngagementMap down =
        mesh_engagement_near("flat:10,20", {{0, 0, 0}, {60, 20.0 - r + ae, kTop}}, kPass, kSteady);
    test::expect_discs(down, 0.0, 2.9, kPi - std::acos(1.0 - ae / r), kPi, kAngle);
    EXPECT_NEAR(down.phi_entry, kPi - std::acos(1.0 - ae / r), kAngle);
    EXPECT_NEAR(down.phi_exit, kPi, kAngle);
  }
}

// Where a boundary is a grazing line (f = 0: the sides of a slot, the rim of a ramp's cut), the
// faceted sweep's wall lies inside the true one by the facets' depth Δ there, and a cell of the
// true surface reaches past it only from an angle acos(1 - Δ/ρ) ≈ √(2Δ/ρ) on: half a facet
// angle for the rings' chords, more on a curved profile, where the profile's chords (sagitta
// h, horizontal depth h/n_ρ) add to it. The flat end mill's cylinder above escapes this only
// because its rings have a vertex on each side of a feed along X.
double grazing_bound(double rho, double n_rho, double facet_depth) {
  const double depth = facet_depth + facet_depth / n_rho;
  return std::acos(std::max(-1.0, 1.0 - depth / rho));
}

// A bull-nose end mill (corner radius 2) slotting 3 mm deep: the torus and the cylinder engage
// the front half, each disc from its grazing line on one side to the other's; the flat bottom
// grazes.
TEST(MeshEngagement, BullNoseSlot) {
  const EngagementMap map =
      mesh_engagement_near("bull:10,2,20", {{0, 0, 0}, {60, 40, kTop}}, kPass, kSteady);
  const double h = MeshWorkpiece::facet_depth(cutter_from_spec("bull:10,2,20"), kFacet);
  int checked = 0;
  for (const DiscEngagement& disc : map.discs) {
    if (disc.z0 < 0.3 || disc.z1 > 2.9) continue;
    const double z = 0.5 * (disc.z0 + disc.z1);
    // The corner arc about (3, 2): ρ = 3 + √(4 - (2 - z)²), n_ρ = (ρ - 3) / 2.
    const double rho = z < 2.0 ? 3.0 + std::sqrt(4.0 - (2.0 - z) * (2.0 - z)) : 5.0;
    const double n_rho = (rho - 3.0) / 2.0;
    const double tolerance = kAngle + grazing_bound(rho, n_rho, h);
    SCOPED_TRACE(testing::Message() << "disc " << disc.z0 << " ρ " << rho);
    ASSERT_EQ(disc.phi.size(), 1u);
    EXPECT_NEAR(disc.phi[0].lo, 0.0, tolerance);
    EXPECT_NEAR(disc.phi[0].hi, kPi, tolerance);
    ++checked;
  }
  EXPECT_GT(checked, 20);
  EXPECT_NEAR(map.axial_depth, 3.0, kSpacing);
  for (const RingEngagement& ring : map.rings) EXPECT_TRUE(ring.phi.empty());
}

// A ball end mill of radius R ramping down into solid stock at angle γ: a disc at height z < R
// engages φ within ψ(z) = acos(-(R - z) tan γ / √(2Rz - z²)) of the feed direction (φ = 90°),
// the whole ring below z = R(1 - cos γ) (engagement_test.cpp, BallEndRamp). ψ is a grazing
// line (f = 0), so the faceting bound applies: at 0.25 mm facets.
TEST(MeshEngagement, BallEndRamp) {
  const double r = 5.0, facet = 0.25;
  const double h = MeshWorkpiece::facet_depth(cutter_from_spec("ball:10,8"), facet);
  for (const double gamma_deg : {15.0, 30.0}) {
    SCOPED_TRACE(testing::Message() << "ramp " << gamma_deg << "°");
    const double tan_g = std::tan(gamma_deg * kDeg);
    const Vec3 start(-10, 20, 30), end(20, 20, 30 - 30 * tan_g);
    const EngagementMap map =
        mesh_engagement_near("ball:10,8", {{0, 12, 5}, {24, 28, 40}}, {line(start, end)},
                             start + (end - start) * (28.0 / 30.0), facet);
    int checked = 0;
    for (const DiscEngagement& disc : map.discs) {
      const double z = 0.5 * (disc.z0 + disc.z1);
      if (z < 0.3 || z > r - 0.3) continue;  // ψ(z) is steep at the tip and the equator
      const double rho = std::sqrt(2 * r * z - z * z);
      const auto psi_at = [&](double height) {
        const double k = (r - height) * tan_g / std::sqrt(2 * r * height - height * height);
        return k >= 1.0 ? kPi : std::acos(-k);
      };
      const double psi = psi_at(z);
      // Within a disc's height of the height where the whole circle engages, the disc's circle
      // runs along the grazing circle behind: skip it (as the dexel test does).
      if (psi_at(z + kSpacing) < kPi && psi >= kPi) continue;
      // The disc's height spread moves ψ by up to |ψ(z ± s/2) - ψ(z)|.
      const double tolerance = kAngle + grazing_bound(rho, rho / r, h) +
                               std::abs(psi_at(z + kSpacing) - psi) +
                               std::abs(psi_at(z - 0.5 * kSpacing) - psi);
      SCOPED_TRACE(testing::Message() << "z " << z << " ρ " << rho);
      // The faceted surface may split a boundary's neighbourhood or pull an end off φ = 0 (a
      // facet grazing where the true surface does not): gaps narrower than the tolerance are
      // closed first, and ends at 0° and 360° are held to the tolerance too.
      std::vector<Interval> phi;
      for (const Interval& i : disc.phi) {
        if (!phi.empty() && i.lo - phi.back().hi < tolerance) {
          phi.back().hi = i.hi;
        } else {
          phi.push_back(i);
        }
      }
      if (psi >= kPi) {
        ASSERT_EQ(phi.size(), 1u);
        EXPECT_EQ(phi[0].lo, 0.0);
        EXPECT_EQ(phi[0].hi, 2 * kPi);
      } else {
        // The piece before φ = 360° is ψ - 90° wide: within the tolerance it may be missing.
        ASSERT_EQ(phi.size(), psi - kPi / 2 < tolerance ? phi.size() : 2u);
        ASSERT_GE(phi.size(), 1u);
        EXPECT_NEAR(phi[0].lo, 0.0, tolerance);
        EXPECT_NEAR(phi[0].hi, kPi / 2 + psi, tolerance);
        if (phi.size() == 2) {
          EXPECT_NEAR(phi[1].lo, 2 * kPi - (psi - kPi / 2), tolerance);
          EXPECT_NEAR(phi[1].hi, 2 * kPi, tolerance);
        }
      }
      ++checked;
    }
    EXPECT_GT(checked, 30);
  }
}

// Convergence in the facet size (the thesis's fig. 6.54 compares 6, 4 and 2 mm facets): the
// engaged area of the bull-nose slot above against the closed form, the front half of the
// profile's surface up to 3 mm: π ∫ρ ds = π (2 (3π/2 + 2) + 5·1) mm² (the corner arc from
// (3, 0) to (5, 2), then the cylinder). Where a ring of the faceted tool has no vertex on a side
// of the feed, its extreme there is an edge parallel to the feed, which grazes its own wall over
// half a facet angle π/n: the area can lose that much on one side of each disc, a fraction 1/n
// of it, n the sides of the smallest ring engaged (ρ = 3). n grows as 1/facet, and so does the
// bound.
TEST(MeshEngagement, AreaConvergesWithTheFacetSize) {
  const double exact = kPi * (2.0 * (1.5 * kPi + 2.0) + 5.0);
  const Cutter cutter = cutter_from_spec("bull:10,2,20");
  for (const double facet : {4.0, 2.0, 1.0, 0.5}) {
    SCOPED_TRACE(testing::Message() << "facet " << facet);
    const EngagementMap map =
        mesh_engagement_near("bull:10,2,20", {{0, 0, 0}, {60, 40, kTop}}, kPass, kSteady, facet);
    const int n = ring_sides(3.0, MeshWorkpiece::facet_depth(cutter, facet));
    EXPECT_LE(map.area, exact * (1.0 + 1e-3));
    EXPECT_GE(map.area, exact * (1.0 - 1.0 / n));
  }
}

// The thesis's accuracy experiment (Aras 2008 fig. 6.54: about 4 % at 6 mm facets, under 1 % at
// 2 mm) on the cases with an exact area: a flat and a ball end mill D = 10, 3 mm deep, in a full
// slot (πRd: half a cylinder; half a spherical zone) and at half immersion (half of it), at 6,
// 4, 2, 1, 0.5 and 0.25 mm facets. Where a cut meets the block's face the boundary is exact;
// along a grazing line (both sides of a slot, one at half immersion) a ring whose polygon has no
// vertex on the side is off by up to half its facet angle π/n(ρ), so the area by at most
// ∫ π/n(ρ(z))·ρ ds per grazing line: R·∫ π/n dz on a ball (ρ ds = R dz), R·d·π/n on the flat.
// The figures are in docs/engagement.md; the ball's slot error falls about as the facet size.
TEST(MeshEngagement, AreaAtTheThesisFacetSizes) {
  const double r = 5.0, depth = 3.0, slot = kPi * r * depth;
  for (const bool ball : {false, true}) {
    const char* spec = ball ? "ball:10,20" : "flat:10,20";
    const Cutter cutter = cutter_from_spec(spec);
    for (const double facet : {6.0, 4.0, 2.0, 1.0, 0.5, 0.25}) {
      const double h = MeshWorkpiece::facet_depth(cutter, facet);
      double grazing = 0.0;  // the area bound of one grazing line
      const double dz = 0.001;
      for (double z = 0.5 * dz; z < depth; z += dz) {
        const double rho = ball ? std::sqrt(z * (2.0 * r - z)) : r;
        grazing += r * kPi / ring_sides(rho, h) * dz;
      }
      for (const double y0 : {0.0, 20.0}) {  // the block's edge: a slot; half immersion
        SCOPED_TRACE(testing::Message() << spec << ", facet " << facet << ", edge " << y0);
        const double exact = y0 == 0.0 ? slot : slot / 2.0;
        const EngagementMap map =
            mesh_engagement_near(spec, {{0, y0, 0}, {60, 40, kTop}}, kPass, kSteady, facet);
        // Plus the grid's own discretisation, a cell (0.1 mm) along each boundary: under 0.1 %.
        EXPECT_NEAR(map.area, exact, (y0 == 0.0 ? 2.0 : 1.0) * grazing + 1e-3 * exact);
        // The table of docs/engagement.md.
        std::printf("%s, %s, %g mm facets: area %.4f mm², error %+.3f %%, bound %.1f %%\n", spec,
                    y0 == 0.0 ? "slot" : "half immersion", facet, map.area,
                    100.0 * (map.area - exact) / exact,
                    100.0 * (y0 == 0.0 ? 2.0 : 1.0) * grazing / exact);
      }
    }
  }
}

// A 3+2 pass: a flat end mill tilted 20° sideways (axis in the XZ plane) cutting 3 mm deep
// along Y into the block's side, against the dexel workpiece's maps at the same locations. The
// two methods differ by their own bounds: the dexel's s/(√2ρ) + 0.1° (engagement_test.cpp) and
// the mesh's 1° plus half a facet angle π/n where a ring grazes its own wall.
// The maps of both methods at the location nearest `probe` (on move `on_move` of `moves` when
// it is not negative) agree within `tolerance` on every disc both engage.
void expect_agrees_with_dexel(const char* tool, const Aabb& block, const std::vector<Move>& moves,
                              const Vec3& probe, double facet, double subdivision, double tolerance,
                              int on_move = -1) {
  const EngagementMap mesh =
      mesh_engagement_near(tool, block, moves, probe, facet, subdivision, on_move);
  test::expect_agrees_with_dexel(
      mesh, test::dexel_map_near(moves, tool, block, kSpacing, subdivision, probe, on_move),
      tolerance, kSpacing);
}

// A flat end mill D = 8 tilted 20° sideways, 3 mm deep along the block's edge (3+2): the same
// map as the dexel method's at the same location. Both are held to their own bounds: the
// dexel's cell s/(√2·R) and 0.1° of the bisection, the mesh's 1° and its edge grazing π/n.
TEST(MeshEngagement, TiltedThreePlusTwoAgreesWithTheDexelMethod) {
  const double facet = 0.25, r = 4.0;
  const Vec3 axis(std::sin(20 * kDeg), 0.0, std::cos(20 * kDeg));
  Move pass = line({28, -10, kTop - 3}, {28, 50, kTop - 3});
  pass.start_axis = pass.end_axis = axis;
  const int n = ring_sides(r, MeshWorkpiece::facet_depth(cutter_from_spec("flat:8,20"), facet));
  expect_agrees_with_dexel("flat:8,20", {{0, 0, 0}, {30, 40, kTop}}, {pass}, Vec3(28, 20, kTop - 3),
                           facet, 0.0,
                           kSpacing / (std::sqrt(2.0) * r) + 0.1 * kDeg + kAngle + kPi / n);
}

// The same pass with the tilt swinging from 10° to 30° along it (simultaneous 5-axis): the
// mesh's RV is read in 3-D, the move is cut in pieces within the subdivision tolerance t (both
// methods the same pieces), and each method's tool at a location lies within t/2 of the piece
// that swept it, which moves a boundary by up to (t/2)/R more in each: t/R in all, on top of
// the 3+2 bounds. At t = 0.1 mm (38 pieces for this 10 mm tool) and 0.5 mm facets.
TEST(MeshEngagement, SimultaneousFiveAxisAgreesWithTheDexelMethod) {
  const double facet = 0.5, r = 4.0, t = 0.1;
  Move pass = line({28, -10, kTop - 3}, {28, 50, kTop - 3});
  pass.start_axis = Vec3(std::sin(10 * kDeg), 0.0, std::cos(10 * kDeg));
  pass.end_axis = Vec3(std::sin(30 * kDeg), 0.0, std::cos(30 * kDeg));
  const int n = ring_sides(r, MeshWorkpiece::facet_depth(cutter_from_spec("flat:8,10"), facet));
  expect_agrees_with_dexel("flat:8,10", {{0, 0, 0}, {30, 40, kTop}}, {pass}, Vec3(28, 20, kTop - 3),
                           facet, t,
                           kSpacing / (std::sqrt(2.0) * r) + 0.1 * kDeg + kAngle + kPi / n + t / r);
}

// The first location of a 5-axis move that goes on from another: the move before must not have
// taken what this location cuts. (Swept with each piece's mean axis, the last piece's tool
// reached up to t beyond the true tool at the joint, and the mesh found the discs' entry near
// 90° instead of 0°; each piece is now the hull of its end tools in their own poses.) That hull
// still exceeds the motion's sweep where the two poses' union is concave, by about z·δ at height
// z for a turn δ = 2t/reach per piece, which a t of the mesh job's default (the facets' depth
// scale, here 0.025 mm) keeps within the bound; at t = 0.1 the entry moves 11°.

TEST(MeshEngagement, FiveAxisMoveStartsWhereTheMoveBeforeEnded) {
  const double facet = 0.5, r = 4.0, t = 0.025;
  const Vec3 joint(28, 15, kTop - 3);
  Move first = line({28, -10, kTop - 3}, joint), second = line(joint, {28, 50, kTop - 3});
  first.start_axis = Vec3(std::sin(20 * kDeg), 0.0, std::cos(20 * kDeg));
  first.end_axis = second.start_axis = Vec3(std::sin(30 * kDeg), 0.0, std::cos(30 * kDeg));
  second.end_axis = Vec3(std::sin(20 * kDeg), 0.0, std::cos(20 * kDeg));
  const int n = ring_sides(r, MeshWorkpiece::facet_depth(cutter_from_spec("flat:8,10"), facet));
  expect_agrees_with_dexel(
      "flat:8,10", {{0, 0, 0}, {30, 40, kTop}}, {first, second}, joint, facet, t,
      kSpacing / (std::sqrt(2.0) * r) + 0.1 * kDeg + kAngle + kPi / n + t / r, 1);
}

// A helix passes over its own path: at a location on its third turn, the RV in front of the
// tool above the first turn's floor (1 mm pitch higher) was taken a turn before, and is not
// engaged. Only the bore's wall at radius R_helix + r touches the side there, along a grazing
// line (the dexel method finds it 1.2° wide); below, the ramp engages the front half.
TEST(MeshEngagement, HelixDoesNotEngageWhatItsLastTurnTook) {
  Move helix;
  helix.shape = MoveShape::kArc;
  helix.feed_rate = 400.0;
  helix.normal = Vec3::UnitZ();  // G3
  helix.center = Vec3(30, 20, kTop + 0.5);
  helix.start = helix.center + Vec3(6, 0, 0);
  helix.sweep = 3 * kTwoPi;  // three turns
  helix.axial = -3.0;        // 1 mm a turn
  helix.end = helix.position(1.0);
  const Vec3 probe = helix.position(0.9);  // 2.2 mm deep, 1.2 mm below the turn before
  // Pieces within the facets' depth, as `cwe simulate` cuts them on the mesh workpiece.
  const double h = MeshWorkpiece::facet_depth(cutter_from_spec("flat:10,20"), kFacet);
  const EngagementMap map =
      mesh_engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}}, {helix}, probe, kFacet, h);
  ASSERT_TRUE(map.engaged);
  const int n = ring_sides(5.0, h);
  int above = 0, below = 0;
  for (const DiscEngagement& disc : map.discs) {
    double width = 0.0;
    for (const Interval& phi : disc.phi) width += phi.hi - phi.lo;
    if (disc.z0 > 1.0 + 2 * kSpacing) {
      // The wall's grazing line, widened by the band where Q lies less than h + contact (here
      // 2h) inside the turn before's tool along its normal and so is not known to be taken.
      EXPECT_LE(width, kPi / n + std::acos(1.0 - 2.0 * h / 5.0) + kAngle) << "disc " << disc.z0;
      ++above;
    } else if (disc.z1 < 0.5) {
      // The ramp ahead, one interval: the turn before does not take any of it (on the faceted
      // surface, Q is up to h inside the true tool the earlier pieces are tested with).
      EXPECT_EQ(disc.phi.size(), 1u) << "disc " << disc.z0;
      EXPECT_GE(width, kPi / 2) << "disc " << disc.z0;
      ++below;
    }
  }
  EXPECT_GT(above, 0);
  EXPECT_GT(below, 0);
}

TEST(MeshEngagement, PlungeEngagesTheWholeBottom) {
  const EngagementMap map =
      mesh_engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}},
                           {line({30, 20, kTop + 2}, {30, 20, kTop - 6})}, Vec3(30, 20, kTop - 4));
  ASSERT_FALSE(map.rings.empty());
  for (const RingEngagement& ring : map.rings) {
    ASSERT_EQ(ring.phi.size(), 1u) << ring.r0;
    EXPECT_EQ(ring.phi[0].lo, 0.0);
    EXPECT_EQ(ring.phi[0].hi, 2 * kPi);
  }
  for (const DiscEngagement& disc : map.discs) EXPECT_TRUE(disc.phi.empty()) << disc.z0;
  EXPECT_EQ(map.axial_depth, 0.0);
}

TEST(MeshEngagement, NothingEngagedInAir) {
  const EngagementMap map =
      mesh_engagement_near("bull:10,2,20", {{0, 0, 0}, {60, 40, kTop}},
                           {line({-10, 20, kTop + 1}, {50, 20, kTop + 1})}, Vec3(25, 20, kTop + 1));
  EXPECT_FALSE(map.engaged);
}

}  // namespace
}  // namespace cwe
