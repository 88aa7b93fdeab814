// Stock from closed triangle meshes (TriDexel::from_mesh) against exact chords.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cwe/core/error.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"
#include "random.hpp"

namespace cwe {
namespace {

TriangleMesh box_mesh(const Aabb& box) {
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k) {
    corners.emplace_back(k & 1 ? box.max.x() : box.min.x(), k & 2 ? box.max.y() : box.min.y(),
                         k & 4 ? box.max.z() : box.min.z());
  }
  return convex_hull(corners);
}

TriangleMesh flipped(TriangleMesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

// Interval ends are floats from the domain's lower face: 1e-5 mm covers their rounding for
// domains up to ~100 mm.
constexpr double kFloat = 1e-5;

void expect_rays_equal(const TriDexel& a, const TriDexel& b) {
  ASSERT_EQ(a.ray_count(), b.ray_count());
  for (int axis = 0; axis < 3; ++axis) {
    ASSERT_EQ(a.grid(axis), b.grid(axis));
    for (int j = 0; j < a.grid(axis)[1]; ++j) {
      for (int i = 0; i < a.grid(axis)[0]; ++i) {
        ASSERT_EQ(a.at(axis, i, j).intervals(), b.at(axis, i, j).intervals())
            << "family " << axis << " ray " << i << ", " << j;
      }
    }
  }
}

TEST(TriDexelFromMesh, BoxMeshGivesTheBoxStock) {
  // Sides that are whole multiples of s and not: the grids and rays must match from_box's.
  for (const Aabb& box :
       {Aabb{{-5, 0, -10}, {25, 20, 0}}, Aabb{{0.1, 0.2, 0.3}, {7.3, 4.45, 3.1}}}) {
    const TriDexel from_box = TriDexel::from_box(box, 0.25);
    const TriDexel from_mesh = TriDexel::from_mesh(box_mesh(box), 0.25, "box.stl");
    EXPECT_EQ(from_mesh.domain().min, from_box.domain().min);
    expect_rays_equal(from_mesh, from_box);
    // An inside-out box is read as the same solid (non-zero winding).
    expect_rays_equal(TriDexel::from_mesh(flipped(box_mesh(box)), 0.25, "box.stl"), from_box);
    EXPECT_EQ(from_mesh.memory().heap_bytes, 0u);
  }
}

TEST(TriDexelFromMesh, RaysThroughVerticesAndEdgesDoNotLeak) {
  // The octahedron |x| + |y| + |z| ≤ R centred on a lattice point (R = 4.5 s): the rays through
  // the centre pass exactly through two vertices, and every ray in a coordinate plane through the
  // centre runs along the projection of an edge. Each ray's material is [-(R - |u| - |v|), +…].
  const double s = 0.5, R = 2.25;
  const Vec3 c(1, 2, 3);
  std::vector<Vec3> v;
  for (int a = 0; a < 3; ++a) {
    v.push_back(c + R * Vec3::Unit(a));
    v.push_back(c - R * Vec3::Unit(a));
  }
  const TriangleMesh octahedron = convex_hull(v);
  ASSERT_EQ(octahedron.triangles.size(), 8u);
  const TriDexel d = TriDexel::from_mesh(octahedron, s, "octahedron");
  int through_vertices = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int j = 0; j < d.grid(axis)[1]; ++j) {
      for (int i = 0; i < d.grid(axis)[0]; ++i) {
        const Ray ray = d.ray(axis, i, j);
        const Vec3 q = ray.origin - c;
        const double u = q[(axis + 1) % 3], w = q[(axis + 2) % 3];
        const double half = R - std::abs(u) - std::abs(w);
        const auto got = d.at(axis, i, j).intervals();
        if (half <= 0.0) {
          EXPECT_TRUE(got.empty()) << axis << " " << i << " " << j;
          continue;
        }
        if (u == 0.0 && w == 0.0) ++through_vertices;
        ASSERT_EQ(got.size(), 1u) << axis << " " << i << " " << j;
        const double centre = c[axis] - d.domain().min[axis];
        EXPECT_NEAR(got[0].lo, centre - half, kFloat);
        EXPECT_NEAR(got[0].hi, centre + half, kFloat);
      }
    }
  }
  EXPECT_EQ(through_vertices, 3);  // one per family
  // Rays sit on lattice points symmetric about the centre: volume of the octahedron (4/3 R³)
  // to within the midpoint rule's error on the pyramid faces (area × s at most).
  for (const double family : d.volume().by_family) {
    EXPECT_NEAR(family, 4.0 / 3.0 * R * R * R, 8 * std::sqrt(3.0) / 2 * R * R * s);
  }
}

// Chord of a ray through a convex closed mesh by clipping against every triangle's plane.
Interval convex_chord(const TriangleMesh& m, const Ray& ray) {
  double lo = -1e300, hi = 1e300;
  for (const auto& t : m.triangles) {
    const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Vec3 n = (m.vertices[static_cast<std::size_t>(t[1])] - a)
                       .cross(m.vertices[static_cast<std::size_t>(t[2])] - a);
    const double along = n.dot(ray.direction), at = n.dot(ray.origin - a);  // n·p ≤ n·a inside
    if (along == 0.0) {
      if (at > 0.0) return Interval::empty();
      continue;
    }
    const double t0 = -at / along;
    if (along > 0.0)
      hi = std::min(hi, t0);
    else
      lo = std::max(lo, t0);
  }
  return lo < hi ? Interval{lo, hi} : Interval::empty();
}

TEST(TriDexelFromMesh, RandomConvexMeshesMatchExactChords) {
  test::Random random(5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> points;
    for (int k = 0; k < 30; ++k) points.push_back(random.point_in_box(5.0));
    const TriangleMesh hull = convex_hull(points);
    const double s = random.uniform(0.2, 0.5);
    const TriDexel d = TriDexel::from_mesh(hull, s, "hull");
    int compared = 0;
    for (int axis = 0; axis < 3; ++axis) {
      for (int j = 0; j < d.grid(axis)[1]; ++j) {
        for (int i = 0; i < d.grid(axis)[0]; ++i) {
          const Interval exact = convex_chord(hull, d.ray(axis, i, j));
          const auto got = d.at(axis, i, j).intervals();
          // Snapping moves vertices by ≤ s·2⁻²¹ across the ray; on faces steeper than 1:100 that
          // shifts a crossing by ≤ 1e-5 mm. Rays within that of an edge may go either way.
          const double tolerance = 1e-4;
          if (exact.is_empty() || exact.length() < tolerance) {
            EXPECT_LE(got.size(), 1u);
            if (!got.empty()) {
              EXPECT_LT(got[0].length(), 2 * tolerance);
            }
            continue;
          }
          ASSERT_EQ(got.size(), 1u) << trial << ": " << axis << " " << i << " " << j;
          EXPECT_NEAR(got[0].lo, exact.lo, tolerance);
          EXPECT_NEAR(got[0].hi, exact.hi, tolerance);
          ++compared;
        }
      }
    }
    EXPECT_GT(compared, 100);
    // Each family's volume estimate converges on the hull's volume (error ≤ area × s).
    for (const double family : d.volume().by_family) {
      EXPECT_NEAR(family, hull.volume(), hull.area() * s);
    }
  }
}

TEST(TriDexelFromMesh, CavityGivesTwoIntervals) {
  // A 10 mm cube with a 4 mm cubic void (its faces facing inwards).
  TriangleMesh m = box_mesh(Aabb{{0, 0, 0}, {10, 10, 10}});
  m.append(flipped(box_mesh(Aabb{{3, 3, 3}, {7, 7, 7}})));
  const TriDexel d = TriDexel::from_mesh(m, 0.5, "hollow");
  for (const double family : d.volume().by_family) EXPECT_NEAR(family, 1000.0 - 64.0, 1e-9);
  EXPECT_EQ(d.at(2, 10, 10).intervals(), (std::vector<Interval>{{0, 3}, {7, 10}}));
  EXPECT_EQ(d.at(2, 1, 1).intervals(), (std::vector<Interval>{{0, 10}}));
  EXPECT_FALSE(d.contains(Vec3(5, 5, 5)));
  EXPECT_TRUE(d.contains(Vec3(5, 5, 2)));
}

TEST(TriDexelFromMesh, RefusesOpenMeshesSayingWhere) {
  TriangleMesh m = box_mesh(Aabb{{0, 0, 0}, {10, 10, 10}});
  m.triangles.pop_back();
  try {
    TriDexel::from_mesh(m, 0.5, "part.stl");
    FAIL() << "an open mesh was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("part.stl"), std::string::npos) << what;
    EXPECT_NE(what.find("3 boundary edges"), std::string::npos) << what;
    EXPECT_NE(what.find(" at ("), std::string::npos) << what;
  }
  // Three triangles on one edge.
  TriangleMesh fin = box_mesh(Aabb{{0, 0, 0}, {10, 10, 10}});
  fin.vertices.emplace_back(20, 20, 20);
  const auto& t = fin.triangles.front();
  fin.triangles.push_back({t[0], t[1], static_cast<int>(fin.vertices.size()) - 1});
  try {
    TriDexel::from_mesh(fin, 0.5, "fin.stl");
    FAIL() << "a non-manifold mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold"), std::string::npos) << e.what();
  }
  EXPECT_THROW(TriDexel::from_mesh(TriangleMesh{}, 0.5, "empty.stl"), InputError);
}

}  // namespace
}  // namespace cwe
