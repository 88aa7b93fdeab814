#include "cwe/geometry/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "random.hpp"

namespace cwe {
namespace {

TEST(TriangleMesh, HullOfACubeIsClosedWithItsVolume) {
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i)
    points.emplace_back(i & 1 ? 2.0 : 0.0, i & 2 ? 3.0 : 0.0, i & 4 ? 4.0 : 0.0);
  points.emplace_back(1, 1, 1);  // an interior point is dropped
  const TriangleMesh hull = convex_hull(points);
  EXPECT_TRUE(check_closure(hull).closed());
  EXPECT_NEAR(hull.volume(), 24.0, 1e-12);
  EXPECT_NEAR(hull.area(), 2 * (6 + 8 + 12), 1e-12);
  EXPECT_EQ(hull.vertices.size(), 8u);
}

TEST(TriangleMesh, HullOfSpherePointsApproachesTheBall) {
  test::Random random(31);
  std::vector<Vec3> points;
  for (int i = 0; i < 4000; ++i) points.push_back(3.0 * random.unit_vector());
  const TriangleMesh hull = convex_hull(points);
  const MeshClosure c = check_closure(hull);
  EXPECT_TRUE(c.closed());
  // An inscribed polytope: below the ball's volume, within a few per cent at 4000 points.
  EXPECT_LT(hull.volume(), 4.0 / 3.0 * kPi * 27.0);
  EXPECT_GT(hull.volume(), 0.97 * 4.0 / 3.0 * kPi * 27.0);
}

TEST(TriangleMesh, HullIsTheSameMeshWhateverTheInputOrder) {
  // A 16-sided prism (two planar caps of 16 vertices, 16 planar side rectangles), as a swept
  // cylinder gives, with points inside and on the faces: CGAL splits planar facets in an order
  // of its own; the mesh written must depend on the point set only.
  std::vector<Vec3> points;
  for (int k = 0; k < 16; ++k) {
    const double a = kTwoPi * k / 16;
    for (const double z : {-5.0, 50.0}) points.emplace_back(7.5 * std::cos(a), 7.5 * std::sin(a), z);
    points.emplace_back(3.0 * std::cos(a), 3.0 * std::sin(a), 10.0);  // inside
    points.emplace_back(2.0 * std::cos(a), 2.0 * std::sin(a), 50.0);   // on the top cap
  }
  const TriangleMesh reference = convex_hull(points);
  ASSERT_TRUE(check_closure(reference).closed());
  EXPECT_EQ(reference.vertices.size(), 32u);
  // 14 triangles per cap fan, 2 per side rectangle.
  EXPECT_EQ(reference.triangles.size(), 2u * 14u + 16u * 2u);
  test::Random random(5);
  for (int trial = 0; trial < 20; ++trial) {
    for (std::size_t i = points.size() - 1; i > 0; --i) {
      std::swap(points[i], points[static_cast<std::size_t>(random.uniform(0.0, static_cast<double>(i) + 0.999))]);
    }
    const TriangleMesh hull = convex_hull(points);
    ASSERT_EQ(hull.vertices, reference.vertices) << trial;
    ASSERT_EQ(hull.triangles, reference.triangles) << trial;
  }
  // Each cap is a fan from its lowest vertex: every cap triangle holds that vertex.
  for (const double z : {-5.0, 50.0}) {
    int lowest = -1, cap_triangles = 0;
    for (std::size_t v = 0; v < reference.vertices.size(); ++v) {
      if (reference.vertices[v].z() == z && lowest < 0) lowest = static_cast<int>(v);
    }
    for (const auto& t : reference.triangles) {
      if (reference.vertices[static_cast<std::size_t>(t[0])].z() != z ||
          reference.vertices[static_cast<std::size_t>(t[1])].z() != z ||
          reference.vertices[static_cast<std::size_t>(t[2])].z() != z) {
        continue;
      }
      ++cap_triangles;
      EXPECT_EQ(t[0], lowest) << "cap z = " << z;  // triangles start at their lowest vertex
    }
    EXPECT_EQ(cap_triangles, 14) << "cap z = " << z;
  }
}

TEST(TriangleMesh, DegenerateInputGivesNoHull) {
  EXPECT_TRUE(convex_hull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}).empty());
  EXPECT_TRUE(convex_hull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}).empty());
}

TEST(TriangleMesh, ClosureCountsBrokenEdges) {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  EXPECT_TRUE(check_closure(m).closed());
  EXPECT_NEAR(m.volume(), 1.0 / 6.0, 1e-15);
  EXPECT_TRUE(check_closure(m).boundary_examples.empty());
  m.triangles.pop_back();
  const MeshClosure open = check_closure(m);
  EXPECT_EQ(open.boundary_edges, 3);
  // The examples are the missing face's edges, lower vertex index first: 0-2, 0-3, 2-3.
  ASSERT_EQ(open.boundary_examples.size(), 3u);
  EXPECT_EQ(open.boundary_examples[0][0], Vec3(0, 0, 0));
  EXPECT_EQ(open.boundary_examples[0][1], Vec3(0, 1, 0));
  EXPECT_EQ(open.boundary_examples[2][0], Vec3(0, 1, 0));
  EXPECT_EQ(open.boundary_examples[2][1], Vec3(0, 0, 1));
  m.triangles.push_back({0, 2, 3});  // wrong orientation
  const MeshClosure flipped = check_closure(m);
  EXPECT_EQ(flipped.misoriented_edges, 3);
  EXPECT_EQ(flipped.misoriented_examples.size(), 3u);
  EXPECT_TRUE(flipped.boundary_examples.empty());
}

// Two tetrahedra sharing only a vertex are two parts (a vertex joins no faces), each closed
// with its own vertices and its own volume; a third, apart, is a third part.
TEST(TriangleMesh, EdgeConnectedPartsMeetAtAVertexAtMost) {
  TriangleMesh m;
  const std::vector<std::array<int, 3>> faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (const Vec3& at : {Vec3(0, 0, 0), Vec3(-1, -1, -1), Vec3(5, 5, 5)}) {
    const int base = static_cast<int>(m.vertices.size());
    // The first two share the vertex (0, 0, 0): the second's corner at (1, 1, 1) from it.
    for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}) {
      m.vertices.push_back(at == Vec3(-1, -1, -1) ? Vec3(-p.x(), -p.y(), -p.z()) : at + p);
    }
    for (const auto& f : faces) {
      m.triangles.push_back(at == Vec3(-1, -1, -1)
                                ? std::array<int, 3>{base + f[0], base + f[2], base + f[1]}
                                : std::array<int, 3>{base + f[0], base + f[1], base + f[2]});
    }
  }
  // Weld the shared corner, as the STL reader would.
  for (auto& t : m.triangles) {
    for (int& v : t) {
      if (v == 4) v = 0;
    }
  }
  const std::vector<TriangleMesh> parts = edge_connected_parts(m);
  ASSERT_EQ(parts.size(), 3u);
  for (const TriangleMesh& part : parts) {
    EXPECT_EQ(part.triangles.size(), 4u);
    EXPECT_EQ(part.vertices.size(), 4u);
    EXPECT_TRUE(check_closure(part).closed());
    EXPECT_NEAR(part.volume(), 1.0 / 6.0, 1e-15);
  }
  EXPECT_EQ(parts[0].vertices[0], Vec3(0, 0, 0));
  EXPECT_EQ(parts[1].vertices[0], Vec3(0, 0, 0));
  EXPECT_EQ(parts[2].vertices[0], Vec3(5, 5, 5));
}

TEST(TriangleMesh, FoldsAreRemovedAndRepeatsKept) {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.5, 0, 0)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const TriangleMesh closed = m;
  // A fold on the edge 0-1 (through the point 4 on it): 0-1 is used five times, 0-4 and 1-4
  // three.
  m.triangles.insert(m.triangles.begin() + 1, {1, 0, 4});
  m.triangles.push_back({4, 1, 0});  // the same turn, from another vertex: not a fold
  m.triangles.push_back({0, 1, 4});  // the opposite turn
  EXPECT_EQ(check_closure(m).non_manifold_edges, 3);
  EXPECT_EQ(remove_folds(m), 2);
  // One of the two same-facing triangles is left, unpaired: check_closure reports it.
  EXPECT_FALSE(check_closure(m).closed());
  ASSERT_EQ(m.triangles.size(), 5u);
  EXPECT_EQ(m.triangles[4], (std::array<int, 3>{4, 1, 0}));
  m.triangles.push_back({1, 4, 0});
  EXPECT_EQ(remove_folds(m), 2);
  EXPECT_EQ(m.triangles, closed.triangles);
  EXPECT_TRUE(check_closure(m).closed());
  EXPECT_NEAR(m.volume(), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(remove_folds(m), 0);
}
}  // namespace
}  // namespace cwe
