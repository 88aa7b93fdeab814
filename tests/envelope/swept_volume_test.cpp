#include "cwe/envelope/swept_volume.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cwe/core/numbers.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"
#include "sweep_oracle.hpp"

namespace cwe {
namespace {

Move line(const Vec3& a, const Vec3& b, const Vec3& axis_a = Vec3::UnitZ(),
          const Vec3& axis_b = Vec3::UnitZ()) {
  return test::line(a, b, axis_a, axis_b);
}

// Inside a closed convex mesh: behind every face plane.
bool convex_contains(const TriangleMesh& mesh, const Vec3& p) {
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vec3 n = (mesh.vertices[static_cast<std::size_t>(t[1])] - a)
                       .cross(mesh.vertices[static_cast<std::size_t>(t[2])] - a);
    if (n.dot(p - a) > 0.0) return false;
  }
  return true;
}

bool pieces_contain(const SweptVolume& v, const Vec3& p) {
  return std::any_of(v.pieces.begin(), v.pieces.end(),
                     [&](const TriangleMesh& m) { return convex_contains(m, p); });
}

TEST(SweptVolume, FlatEndMillSideCutIsAStadiumPrism) {
  const Cutter flat = cutter_from_spec("flat:10,20");
  SweptVolumeOptions options;
  options.tolerance = 0.01;
  const SweptVolume v = swept_volume(flat, line({0, 0, 0}, {30, 0, 0}), options);
  ASSERT_EQ(v.pieces.size(), 1u);
  EXPECT_TRUE(check_closure(v.pieces[0]).closed());
  // Stadium (two half discs and a 10 × 30 rectangle) times the height 20.
  const double exact = (kPi * 25.0 + 10.0 * 30.0) * 20.0;
  const double area = 2 * (kPi * 25.0 + 300.0) + (kPi * 10.0 + 60.0) * 20.0;
  // An inscribed polytope: smaller, by less than its area times the tolerance.
  EXPECT_LT(v.pieces[0].volume(), exact);
  EXPECT_GT(v.pieces[0].volume(), exact - area * options.tolerance);
}

TEST(SweptVolume, BallEndMillMatchesToolPlusSilhouetteTimesLength) {
  const Cutter ball = cutter_from_spec("ball:10,20");
  SweptVolumeOptions options;
  options.tolerance = 0.005;
  const double r = 5.0, h = 20.0, length = 30.0;
  const double tool = 2.0 / 3.0 * kPi * r * r * r + kPi * r * r * (h - r);
  const double area_tool = 2 * kPi * r * r + 2 * kPi * r * (h - r) + kPi * r * r;
  // Horizontal: the silhouette across the feed is a half disc under a 2r × (h - r) rectangle.
  {
    const SweptVolume v = swept_volume(ball, line({0, 0, 0}, {0, length, 0}), options);
    const double exact = tool + length * (kPi * r * r / 2 + 2 * r * (h - r));
    const double area = area_tool + length * (kPi * r + 2 * (h - r) + 2 * r);
    EXPECT_TRUE(check_closure(v.pieces[0]).closed());
    EXPECT_LT(v.pieces[0].volume(), exact);
    EXPECT_GT(v.pieces[0].volume(), exact - area * options.tolerance);
  }
  // Along the axis (a plunge): the tool stretched by the length, a capsule-ended cylinder.
  {
    const SweptVolume v = swept_volume(ball, line({0, 0, 0}, {0, 0, -length}), options);
    const double exact = tool + length * kPi * r * r;
    const double area = area_tool + length * 2 * kPi * r;
    EXPECT_LT(v.pieces[0].volume(), exact);
    EXPECT_GT(v.pieces[0].volume(), exact - area * options.tolerance);
  }
}

// Monte-Carlo membership against the brute-force union of densely sampled tool positions: the
// mesh and the union agree for every point farther than a band from the union's boundary. The
// band is the mesh's deviation bound plus the gap between sampled positions.
void expect_membership_agrees(const Cutter& cutter, const Move& move, double tolerance,
                              int positions, int points, test::Random& random) {
  SweptVolumeOptions options;
  options.tolerance = tolerance;
  const SweptVolume v = swept_volume(cutter, move, options);
  for (const TriangleMesh& piece : v.pieces) ASSERT_TRUE(check_closure(piece).closed());
  Aabb box;
  for (const TriangleMesh& piece : v.pieces) box.extend(piece.bounds());
  box.inflate(1.0);
  const double reach =
      std::hypot(cutter.bounding_cylinder().radius, cutter.bounding_cylinder().z_max);
  const double gap = (move.length() + reach * move.axis_angle()) / positions;
  const double band = v.deviation_bound + gap;
  int decided = 0;
  for (int k = 0; k < points; ++k) {
    const Vec3 p(random.uniform(box.min.x(), box.max.x()), random.uniform(box.min.y(), box.max.y()),
                 random.uniform(box.min.z(), box.max.z()));
    const double d = test::union_signed_distance(cutter, move, p, positions);
    if (std::abs(d) <= band) continue;
    ++decided;
    ASSERT_EQ(pieces_contain(v, p), d < 0.0) << "point " << p.transpose() << " distance " << d;
  }
  EXPECT_GT(decided, points / 2);
}

TEST(SweptVolume, MembershipAgreesWithBruteForceForEveryToolAndMotion) {
  test::Random random(41);
  for (const char* spec :
       {"bull:10,2,20", "taper-flat:6,5,20", "taper-ball:4,3,20", "chamfer:12,90,15",
        "apt:7.8586,1,3,1.5444,10,5,20", "taper-flat:10,-3,20"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    // Ramp down at 20°, a tilted 3+2 move.
    expect_membership_agrees(cutter, line({0, 0, 0}, {20, 5, -7.3}), 0.02, 200, 600, random);
    expect_membership_agrees(cutter,
                             line({0, 0, 0}, {15, -10, 2}, Vec3(0.3, 0.2, 1), Vec3(0.3, 0.2, 1)),
                             0.02, 200, 600, random);
  }
}

TEST(SweptVolume, ArcsHelicesAndFiveAxisStayWithinTheirBound) {
  test::Random random(42);
  const Cutter ball = cutter_from_spec("ball:6,15");
  Move helix;
  helix.shape = MoveShape::kArc;
  helix.center = Vec3(0, 0, 0);
  helix.normal = Vec3::UnitZ();
  helix.start = Vec3(8, 0, 0);
  helix.sweep = 1.5 * kPi;
  helix.axial = -3.0;
  helix.end = helix.position(1.0);
  expect_membership_agrees(ball, helix, 0.02, 1000, 600, random);
  // A 14° axis turn over 25 mm: about 75 pieces at 0.05 mm.
  const Move five_axis = line({0, 0, 0}, {25, 0, 0}, Vec3::UnitZ(), Vec3(0.25, 0, 1));
  SweptVolumeOptions options;
  options.tolerance = 0.05;
  EXPECT_GT(swept_volume(ball, five_axis, options).pieces.size(), 10u);
  expect_membership_agrees(ball, five_axis, 0.05, 1000, 600, random);
}

// Inside a closed mesh: an odd number of crossings by a ray (in a direction none of the test
// meshes' faces contain).
bool mesh_contains(const TriangleMesh& mesh, const Vec3& p) {
  const Vec3 d = Vec3(0.3127, 0.2213, 0.9237).normalized();
  int crossings = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vec3 e1 = mesh.vertices[static_cast<std::size_t>(t[1])] - a;
    const Vec3 e2 = mesh.vertices[static_cast<std::size_t>(t[2])] - a;
    const Vec3 h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-14) continue;
    const Vec3 s = p - a;
    const double u = s.dot(h) / det;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0) ++crossings;
  }
  return crossings % 2 == 1;
}

// An arc of the tip in the plane z = 0 about the origin, from angle `from` through `sweep`
// (counter-clockwise about `normal`), the tool along +Z.
Move planar_arc(double radius, double from, double sweep, const Vec3& normal) {
  Move m;
  m.shape = MoveShape::kArc;
  m.normal = normal;
  m.center = Vec3::Zero();
  const Vec3 e1(std::cos(from), std::sin(from), 0.0);
  m.start = radius * e1;
  m.sweep = sweep;
  m.end = m.position(1.0);
  return m;
}

// A planar arc's sweep from the tool's section revolved: one mesh (half tools at the ends) where
// the inner wall stays off the arc's axis, else the wedge and the tool at both ends. Each mesh
// closed, with no degenerate face, and their union on the right side of the brute-force union
// of the tool's positions at every point farther than the band from its boundary: the tool's
// facets and the stations' chords each within tolerance/2. A flat end mill's one mesh against
// the closed form: an annulus sector 2r wide plus the tool's disc, times the height, within
// its area times the tolerance.
TEST(SweptVolume, PlanarArcWithinItsBound) {
  test::Random random(43);
  const double tolerance = 0.02;
  struct Case {
    Move arc;
    std::size_t meshes;  // for a tool of radius 5, 6 (chamfer) or 3 (ball)
  };
  const std::vector<Move> arcs = {
      planar_arc(12.0, 0.3, kPi / 2, -Vec3::UnitZ()),    // G2: one mesh
      planar_arc(8.0, -1.0, 1.25 * kPi, Vec3::UnitZ()),  // G3, most of a turn
      planar_arc(7.0, 0.0, kTwoPi, -Vec3::UnitZ()),      // a full circle: one mesh
      planar_arc(5.0, 0.5, kPi / 2, -Vec3::UnitZ()),     // a corner: R = r of the flat
      planar_arc(2.0, 0.0, 1.5 * kPi, Vec3::UnitZ()),    // around a corner, R < r
      planar_arc(2.5, 0.0, kTwoPi, Vec3::UnitZ())};      // a circle with R < r: no hole
  for (const char* spec :
       {"flat:10,20", "ball:6,15", "bull:10,2,20", "chamfer:12,90,15", "taper-ball:4,3,20"}) {
    const Cutter cutter = cutter_from_spec(spec);
    const double rho = cutter.profile().max_radius();
    const double reach =
        std::hypot(cutter.bounding_cylinder().radius, cutter.bounding_cylinder().z_max);
    for (const Move& arc : arcs) {
      SCOPED_TRACE(testing::Message()
                   << spec << ", arc R " << arc.radius() << ", " << arc.sweep << " rad");
      const std::vector<TriangleMesh> meshes = planar_arc_sweep(cutter, tolerance, tolerance, arc);
      const bool full = arc.sweep >= kTwoPi;
      const bool glued = arc.radius() - rho > tolerance / 2 &&
                         arc.sweep + 2 * std::asin(rho / arc.radius()) < kTwoPi - 1e-3;
      ASSERT_EQ(meshes.size(), full || glued ? 1u : 3u);
      Aabb box;
      for (const TriangleMesh& mesh : meshes) {
        ASSERT_TRUE(check_closure(mesh).closed());
        ASSERT_GT(mesh.volume(), 0.0);
        for (const auto& t : mesh.triangles) {  // no degenerate face (a point repeated)
          const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
          ASSERT_GT((mesh.vertices[static_cast<std::size_t>(t[1])] - a)
                        .cross(mesh.vertices[static_cast<std::size_t>(t[2])] - a)
                        .norm(),
                    1e-9);
        }
        box.extend(mesh.bounds());
      }
      box.inflate(1.0);
      int decided = 0;
      for (int k = 0; k < 300; ++k) {
        const Vec3 p(random.uniform(box.min.x(), box.max.x()),
                     random.uniform(box.min.y(), box.max.y()),
                     random.uniform(box.min.z(), box.max.z()));
        const int side = test::union_side(cutter, arc, p, tolerance, reach);
        if (side == 0) continue;
        ++decided;
        const bool inside = std::any_of(meshes.begin(), meshes.end(),
                                        [&](const TriangleMesh& m) { return mesh_contains(m, p); });
        ASSERT_EQ(inside, side < 0) << "point " << p.transpose();
      }
      EXPECT_GT(decided, 200);
    }
  }
  const double r = 5.0, height = 20.0, big_r = 12.0;
  const std::vector<TriangleMesh> flat =
      planar_arc_sweep(cutter_from_spec("flat:10,20"), tolerance, tolerance, arcs[0]);
  ASSERT_EQ(flat.size(), 1u);
  // Sweep π/2: the annulus sector's area is (π/2)·2R·r (outer and inner arcs (π/2)(R ± r)).
  const double section = kPi / 2 * 2 * big_r * r + kPi * r * r;
  const double exact = section * height;
  const double area = 2 * section + height * (kPi / 2 * 2 * big_r + kTwoPi * r);
  EXPECT_LT(flat.front().volume(), exact);
  EXPECT_GT(flat.front().volume(), exact - area * tolerance);
}

// Only a planar arc with the tool along its normal is swept this way; any other move is cut in
// pieces.
TEST(SweptVolume, PlanarArcSweepOnlyForPlanarArcs) {
  const Cutter flat = cutter_from_spec("flat:10,20");
  Move helix = planar_arc(8.0, 0.0, 1.0, Vec3::UnitZ());
  helix.axial = -1.0;
  EXPECT_TRUE(planar_arc_sweep(flat, 0.02, 0.02, helix).empty());
  Move tilted = planar_arc(8.0, 0.0, 1.0, Vec3::UnitZ());
  tilted.start_axis = tilted.end_axis = Vec3(0.1, 0.0, 1.0).normalized();
  EXPECT_TRUE(planar_arc_sweep(flat, 0.02, 0.02, tilted).empty());
  EXPECT_TRUE(planar_arc_sweep(flat, 0.02, 0.02, line({0, 0, 0}, {10, 0, 0})).empty());
}

TEST(SweptVolume, RefusesWhatItCannotBuild) {
  const Cutter corner = cutter_from_json(
      R"({"profile": [{"line": [2, 0]}, {"arc": [5, 3], "center": [5, 0], "ccw": false}, {"line": [5, 8]}]})",
      "corner.json");
  EXPECT_FALSE(is_convex(corner));
  EXPECT_THROW(swept_volume(corner, line({0, 0, 0}, {1, 0, 0})), InputError);
  SweptVolumeOptions bad;
  bad.tolerance = 0.0;
  EXPECT_THROW(swept_volume(cutter_from_spec("flat:10"), line({0, 0, 0}, {1, 0, 0}), bad),
               InputError);
  for (const char* spec : {"flat:10", "ball:10", "bull:10,2", "taper-flat:6,5", "taper-flat:10,-3",
                           "taper-ball:4,3", "chamfer:12,90", "apt:7.8586,1,3,1.5444,10,5,20"}) {
    EXPECT_TRUE(is_convex(cutter_from_spec(spec))) << spec;
  }
}

// The volumes from the profile alone (what the B-rep workpiece checks its solids by) against
// closed forms: flat and ball end mills on lines at any slope, and planar arcs.
TEST(SweptVolumeFormulas, LinesAgreeWithClosedForms) {
  const double r = 5.0, h = 20.0, length = 17.0;
  const Cutter flat = cutter_from_spec("flat:10,20");
  EXPECT_NEAR(cutter_volume(flat), kPi * r * r * h, 1e-9 * kPi * r * r * h);
  for (const double deg : {0.0, 10.0, -35.0, 90.0}) {
    const double g = deg * kPi / 180.0;
    const Vec3 d = length * Vec3(0.6 * std::cos(g), 0.8 * std::cos(g), std::sin(g));
    const double exact =
        kPi * r * r * h + length * (2 * r * h * std::cos(g) + kPi * r * r * std::abs(std::sin(g)));
    EXPECT_NEAR(line_swept_volume(flat, d), exact, 1e-8 * exact) << deg;
  }
  // A ball end: the cylinder over a hemisphere; level, its shadow is the rectangle over a half
  // disc; plunging, the disc.
  const Cutter ball = cutter_from_spec("ball:10,20");
  const double tool = kPi * r * r * (h - r) + 2.0 / 3.0 * kPi * r * r * r;
  EXPECT_NEAR(cutter_volume(ball), tool, 1e-8 * tool);
  const double level = tool + length * (2 * r * (h - r) + kPi * r * r / 2);
  EXPECT_NEAR(line_swept_volume(ball, Vec3(length, 0, 0)), level, 1e-8 * level);
  const double plunge = tool + length * kPi * r * r;
  EXPECT_NEAR(line_swept_volume(ball, Vec3(0, 0, -length)), plunge, 1e-8 * plunge);
}

// A flat end mill on arcs: h·(2αRr + πr²) off the arc's axis, h·4πRr for a full ring; round a
// corner (R < r) against the area of the points within r of the arc on a 0.02 mm grid (the
// nearest point of the arc is the radial projection, or the end nearer in angle).
TEST(SweptVolumeFormulas, PlanarArcsAgreeWithClosedFormsAndAGrid) {
  const double r = 5.0, h = 20.0;
  const Cutter flat = cutter_from_spec("flat:10,20");
  const double off = h * (2 * 1.2 * 12.0 * r + kPi * r * r);
  EXPECT_NEAR(planar_arc_swept_volume(flat, 12.0, 1.2), off, 1e-8 * off);
  const double ring = h * 4 * kPi * 12.0 * r;
  EXPECT_NEAR(planar_arc_swept_volume(flat, 12.0, kTwoPi), ring, 1e-8 * ring);
  for (const double big_r : {3.0, 1.0}) {
    const double alpha = 0.5 * kPi, step = 0.02, extent = big_r + r;
    long inside = 0;
    for (double x = -extent; x <= extent; x += step) {
      for (double y = -extent; y <= extent; y += step) {
        // The polar angle within a turn centred on the arc's middle, clamped to its ends.
        double polar = std::atan2(y, x);
        if (polar < 0.5 * alpha - kPi) polar += kTwoPi;
        const double angle = std::clamp(polar, 0.0, alpha);
        const double dx = x - big_r * std::cos(angle), dy = y - big_r * std::sin(angle);
        if (dx * dx + dy * dy <= r * r) ++inside;
      }
    }
    const double grid = h * static_cast<double>(inside) * step * step;
    EXPECT_NEAR(planar_arc_swept_volume(flat, big_r, alpha), grid, 2e-3 * grid) << big_r;
  }
  // Arcs long enough that the end discs overlap beyond the arc's angles (α + 2 asin(ρ/R) > 2π)
  // and corners of 270°: a point is swept when it lies within r of the arc (within r of the
  // circle at an angle inside the arc's, or of either end).
  for (const auto& [big_r, alpha] :
       {std::pair{6.0, 300.0 * kPi / 180.0}, std::pair{5.5, 270.0 * kPi / 180.0},
        std::pair{4.0, 270.0 * kPi / 180.0}}) {
    const double step = 0.02, extent = big_r + r;
    long inside = 0;
    for (double x = -extent; x <= extent; x += step) {
      for (double y = -extent; y <= extent; y += step) {
        double polar = std::atan2(y, x);
        if (polar < 0.0) polar += kTwoPi;
        const double d = std::hypot(x, y) - big_r;
        const bool along = polar <= alpha && std::abs(d) <= r;
        const bool at_start = std::hypot(x - big_r, y) <= r;
        const bool at_end =
            std::hypot(x - big_r * std::cos(alpha), y - big_r * std::sin(alpha)) <= r;
        if (along || at_start || at_end) ++inside;
      }
    }
    const double grid = h * static_cast<double>(inside) * step * step;
    EXPECT_NEAR(planar_arc_swept_volume(flat, big_r, alpha), grid, 2e-3 * grid)
        << big_r << " " << alpha;
  }
}

}  // namespace
}  // namespace cwe
