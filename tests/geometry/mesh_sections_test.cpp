#include "cwe/geometry/mesh_sections.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "random.hpp"

namespace cwe {
namespace {

TriangleMesh box(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                            k & 4 ? hi.z() : lo.z());
  }
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

TEST(MeshSections, ConvexHullAgainstItsPlanesInATiltedFrame) {
  test::Random random(7);
  std::vector<Vec3> points;
  for (int i = 0; i < 600; ++i) points.push_back(3.0 * random.unit_vector());
  const TriangleMesh hull = convex_hull(points);
  const Frame frame = Frame::from_z(Vec3(0.3, -0.2, 0.1), Vec3(1, 1, 1), Vec3::UnitX());
  const MeshSlicer slicer(hull, frame);
  // Inside the hull: on the inner side of every face plane (the hull is convex).
  const auto margin = [&](const Vec3& p) {
    double m = std::numeric_limits<double>::infinity();
    for (const auto& t : hull.triangles) {
      const Vec3& a = hull.vertices[static_cast<std::size_t>(t[0])];
      const Vec3 n = (hull.vertices[static_cast<std::size_t>(t[1])] - a)
                         .cross(hull.vertices[static_cast<std::size_t>(t[2])] - a)
                         .normalized();
      m = std::min(m, -n.dot(p - a));
    }
    return m;
  };
  int inside = 0, checked = 0;
  for (int plane = 0; plane < 40; ++plane) {
    const double h = random.uniform(-3.2, 3.2);
    const MeshSection section = slicer.section(h);
    for (int i = 0; i < 200; ++i) {
      const double u = random.uniform(-3.5, 3.5), v = random.uniform(-3.5, 3.5);
      const double m = margin(frame.to_world(Vec3(u, v, h)));
      if (std::abs(m) < 1e-9) continue;  // on the surface: either answer
      ++checked;
      inside += m > 0.0;
      EXPECT_EQ(section.contains(u, v), m > 0.0) << "h " << h << " at " << u << ", " << v;
    }
  }
  EXPECT_GT(inside, 1000);  // the test reaches both answers often
  EXPECT_GT(checked - inside, 1000);
}

TEST(MeshSections, FacesInThePlaneBelongToTheSolidBelowIt) {
  // Two boxes stacked at z = 1, and a third beside the lower one touching it at x = 1: one mesh
  // of three closed pieces, as a move's removal volume made of several pieces.
  TriangleMesh m = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.append(box(Vec3(0, 0, 1), Vec3(1, 1, 2)));
  m.append(box(Vec3(1, 0, 0), Vec3(2, 1, 1)));
  const MeshSlicer slicer(m, Frame{});
  EXPECT_TRUE(slicer.section(0.0).empty());        // the plane just under the floor
  const MeshSection at_one = slicer.section(1.0);  // just under the common face: the lower two
  EXPECT_TRUE(at_one.contains(0.5, 0.5));
  EXPECT_TRUE(at_one.contains(1.5, 0.5));
  EXPECT_TRUE(at_one.contains(1.0 - 1e-9, 0.25));  // either side of the common face
  EXPECT_TRUE(at_one.contains(1.0 + 1e-9, 0.25));
  EXPECT_FALSE(at_one.contains(2.0 + 1e-9, 0.5));
  EXPECT_FALSE(at_one.contains(-1e-9, 0.5));
  EXPECT_FALSE(at_one.contains(0.5, 1.0 + 1e-9));
  const MeshSection above = slicer.section(1.5);  // the upper box only
  EXPECT_TRUE(above.contains(0.5, 0.5));
  EXPECT_FALSE(above.contains(1.5, 0.5));
  EXPECT_TRUE(slicer.section(2.0).contains(0.5, 0.5));
  EXPECT_TRUE(slicer.section(2.0 + 1e-12).empty());
  // A ray along +u through the vertices of the common face (v = 0 and v = 1 are its edges).
  EXPECT_TRUE(at_one.contains(0.5, 0.0));
  EXPECT_FALSE(at_one.contains(0.5, 1.0));  // the half-open rule: the top edge is outside
}

TEST(MeshSections, EmptyMeshHasEmptySections) {
  const MeshSlicer slicer(TriangleMesh{}, Frame{});
  EXPECT_TRUE(slicer.section(0.0).empty());
  EXPECT_FALSE(slicer.section(0.0).contains(0.0, 0.0));
}

}  // namespace
}  // namespace cwe
