#include "cwe/geometry/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace cwe
