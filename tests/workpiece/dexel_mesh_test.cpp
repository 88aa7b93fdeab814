#include "cwe/workpiece/dexel/dexel_mesh.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// Float storage of dexel interval ends (relative to the domain's lower face) rounds by at most
// half an ulp of the coordinate: 1e-6 mm below 16 mm, so exact crossings agree to this.
constexpr double kFloatRounding = 1e-5;

// Every vertex's triangles form one fan closed around it (the vertex link is a single cycle):
// with check_closure's edge test this makes the mesh a closed 2-manifold.
bool vertices_are_manifold(const TriangleMesh& mesh) {
  std::vector<std::map<int, int>> link(mesh.vertices.size());
  for (const auto& t : mesh.triangles) {
    for (std::size_t v = 0; v < 3; ++v) {
      auto& around = link[static_cast<std::size_t>(t[v])];
      if (!around.emplace(t[(v + 1) % 3], t[(v + 2) % 3]).second) return false;
    }
  }
  for (const auto& around : link) {
    if (around.size() < 3) return false;
    int steps = 0;
    int at = around.begin()->first;
    do {
      const auto next = around.find(at);
      if (next == around.end()) return false;
      at = next->second;
      ++steps;
    } while (at != around.begin()->first && steps <= static_cast<int>(around.size()));
    if (steps != static_cast<int>(around.size())) return false;
  }
  return true;
}

void expect_closed_manifold(const TriangleMesh& mesh) {
  const MeshClosure closure = check_closure(mesh);
  EXPECT_TRUE(closure.closed()) << "boundary " << closure.boundary_edges << " non-manifold "
                                << closure.non_manifold_edges << " misoriented "
                                << closure.misoriented_edges;
  EXPECT_TRUE(vertices_are_manifold(mesh));
  EXPECT_GT(mesh.volume(), 0.0);  // outward normals
}

// The chord of a sphere (empty if the ray misses it); rays are unit.
Interval sphere_chord(const Ray& ray, const Vec3& center, double radius) {
  const Vec3 to_origin = ray.origin - center;
  const double b = ray.direction.dot(to_origin);
  const double discriminant = b * b - (to_origin.squaredNorm() - radius * radius);
  if (discriminant < 0.0) return Interval::empty();
  const double root = std::sqrt(discriminant);
  return {-b - root, -b + root};
}

// The chord of an axis-aligned box along an axis-parallel ray.
Interval box_chord(const Ray& ray, const Aabb& box) {
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] != 0.0) continue;
    if (ray.origin[a] < box.min[a] || ray.origin[a] > box.max[a]) return Interval::empty();
  }
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] != 0.0) return {box.min[a] - ray.origin[a], box.max[a] - ray.origin[a]};
  }
  return Interval::empty();
}

void remove_box(TriDexel& stock, const Aabb& box) {
  stock.remove(box, [box](const Ray& ray) { return box_chord(ray, box); });
}

void remove_sweep(TriDexel& stock, const LinearSweep& sweep) {
  stock.remove(sweep.bounds(), [&sweep](const Ray& ray) { return sweep.chord(ray); });
}

// Box stock: inside the box every lattice point is material and every crossing lies exactly on
// a face, so the mesh is the box with its edges chamfered. A chamfer spans the gaps δ1, δ2 < s
// between the faces and the outermost lattice lines and misses δ1·δ2/2 ≤ s²/2 per millimetre of
// edge (the corners a smaller amount again); nothing is added, and the bounds are the box's own.
// With a stride k the lattice spacing is h = k·s and the same holds with h for s.
void expect_box(const Aabb& box, double spacing, int stride = 1) {
  const TriDexel stock = TriDexel::from_box(box, spacing);
  const TriangleMesh mesh = dexel_mesh(stock, stride);
  const double s = spacing * stride;
  expect_closed_manifold(mesh);
  const Vec3 size = box.size();
  const double edge_length = 4 * (size.x() + size.y() + size.z());
  const double area = 2 * (size.x() * size.y() + size.y() * size.z() + size.z() * size.x());
  EXPECT_LE(mesh.volume(), box.volume() + kFloatRounding * area);
  EXPECT_GE(mesh.volume(), box.volume() - edge_length * s * s / 2);
  EXPECT_NEAR(mesh.volume(), box.volume(), area * s);  // the general bound, far looser
  const Aabb bounds = mesh.bounds();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(bounds.min[a], box.min[a], kFloatRounding);
    EXPECT_NEAR(bounds.max[a], box.max[a], kFloatRounding);
  }
}

TEST(DexelMesh, BoxOnCellBoundaries) { expect_box(Aabb{{0, 0, 0}, {10, 6, 4}}, 0.5); }

TEST(DexelMesh, BoxOnACoarserLattice) {
  expect_box(Aabb{{0, 0, 0}, {10, 6, 4}}, 0.1, 3);
  expect_box(Aabb{{0.13, -0.21, 0.07}, {7.3, 4.9, 3.33}}, 0.2, 2);
  EXPECT_THROW(dexel_mesh(TriDexel::from_box(Aabb{{0, 0, 0}, {1, 1, 1}}, 0.1), 0), InputError);
}

TEST(DexelMesh, StrideForATriangleBudget) {
  // A 20 mm cube at s = 0.1: 6 faces of 200 × 200 crossing rays each, 240,000 crossings, so
  // stride 1 gives about 480,000 triangles (a face cell gives two) and stride k 480,000 / k².
  const TriDexel stock = TriDexel::from_box(Aabb{{0, 0, 0}, {20, 20, 20}}, 0.1);
  EXPECT_EQ(dexel_mesh_stride(stock, 1'000'000), 1);
  const int stride = dexel_mesh_stride(stock, 100'000);
  EXPECT_EQ(stride, 3);  // ⌈√4.8⌉
  const std::size_t triangles = dexel_mesh(stock, stride).triangles.size();
  EXPECT_LE(triangles, 100'000u);
  EXPECT_GT(triangles, 40'000u);  // the estimate is not wildly pessimistic (480,000 / 9)
}

TEST(DexelMesh, BoxOffCellBoundaries) {
  expect_box(Aabb{{0.13, -0.21, 0.07}, {7.3, 4.9, 3.33}}, 0.4);
  expect_box(Aabb{{-3.01, 2.02, 5.5}, {0.03, 3.07, 6.61}}, 0.15);
}

// The exact solid the dexel samples: the block minus the swept volumes. A point is inside a
// sweep when the sweep's chord along +X through it contains it.
struct CarvedBlock {
  Aabb block;
  std::vector<const LinearSweep*> sweeps;
  bool contains(const Vec3& p) const {
    if (!block.contains(p)) return false;
    for (const LinearSweep* sweep : sweeps) {
      if (sweep->bounds().contains(p) && sweep->chord(Ray{p, Vec3::UnitX()}).contains(0.0)) {
        return false;
      }
    }
    return true;
  }
};

// Whether the exact solid's boundary passes within `radius` of p: some sample within that
// distance is inside and another outside (the segment between them lies in the ball and crosses
// the boundary). Samples step radius/8 along the six axis directions, so a vertex on a lattice
// edge sees both of that edge's ends (offsets k·s/8 include every multiple of s/8 up to s).
bool near_boundary(const CarvedBlock& solid, const Vec3& p, double radius) {
  bool inside = false, outside = false;
  for (int step = 1; step <= 8; ++step) {
    for (int a = 0; a < 3; ++a) {
      for (const double sign : {-1.0, 1.0}) {
        const bool in = solid.contains(p + sign * step * radius / 8 * Vec3::Unit(a));
        inside = inside || in;
        outside = outside || !in;
        if (inside && outside) return true;
      }
    }
  }
  return false;
}

// A closed slot (flat end mill, round ends) crossed by a ball-end groove running off the block.
TEST(DexelMesh, SlotAndBallGroove) {
  const Aabb block{{0, 0, 0}, {30, 20, 10}};
  const double s = 0.25;
  TriDexel stock = TriDexel::from_box(block, s);
  const Cutter flat = cutter_from_spec("flat:6,20");
  const Cutter ball = cutter_from_spec("ball:8,20");
  const LinearSweep slot(flat, Vec3(5.1, 6.05, 7.02), Vec3(24.9, 6.05, 7.02), Vec3::UnitZ());
  const LinearSweep groove(ball, Vec3(15.03, -5, 6.5), Vec3(15.03, 25, 6.5), Vec3::UnitZ());
  remove_sweep(stock, slot);
  remove_sweep(stock, groove);

  const TriangleMesh mesh = dexel_mesh(stock);
  expect_closed_manifold(mesh);
  // The vertices are exact surface points, so the mesh departs from the surface only between
  // lattice edges: by the chamfer (≤ s deep) along sharp edges and by the sagitta s²/(8R)
  // across curved faces. Both stay within a band of width s over the area: the general bound.
  const double area = mesh.area();
  EXPECT_NEAR(mesh.volume(), stock.volume().mean(), area * s);
  // The same errors, counted more closely: chamfers miss ≤ s²/2 per millimetre of sharp edge
  // (block 240 mm, slot rim and floor ≈ 2·(2·19.8 + 2π·3) ≈ 117 mm, groove rims ≈ 2·20 + 2·10
  // ... ≈ 100 mm; 500 mm is generous), and the dexel volume differs from the exact solid by
  // the same order.
  EXPECT_NEAR(mesh.volume(), stock.volume().mean(), 500 * s * s);

  const CarvedBlock solid{block, {&slot, &groove}};
  int far = 0;
  for (const Vec3& v : mesh.vertices) far += near_boundary(solid, v, s) ? 0 : 1;
  EXPECT_EQ(far, 0) << "of " << mesh.vertices.size() << " vertices";
}

// Crack test: random moves of random cutters through a small block at a coarse spacing, meshed
// after every move.
TEST(DexelMesh, RandomCutsStayClosed) {
  test::Random random(77);
  const Aabb block{{0, 0, 0}, {8, 7, 5}};
  const std::vector<Cutter> cutters{cutter_from_spec("ball:3,10"), cutter_from_spec("flat:2.5,10"),
                                    cutter_from_spec("bull:4,1,10")};
  for (int trial = 0; trial < 6; ++trial) {
    TriDexel stock = TriDexel::from_box(block, random.uniform(0.3, 0.6));
    for (int move = 0; move < 6; ++move) {
      const Cutter& cutter = cutters[static_cast<std::size_t>(random.integer(0, 2))];
      const Vec3 from(random.uniform(-1, 9), random.uniform(-1, 8), random.uniform(1, 5));
      const Vec3 to(random.uniform(-1, 9), random.uniform(-1, 8), random.uniform(1, 5));
      remove_sweep(stock, LinearSweep(cutter, from, to, Vec3::UnitZ()));
      SCOPED_TRACE(testing::Message() << "trial " << trial << " move " << move);
      for (const int stride : {1, 2}) {
        const TriangleMesh mesh = dexel_mesh(stock, stride);
        if (mesh.empty()) continue;
        expect_closed_manifold(mesh);
        EXPECT_NEAR(mesh.volume(), stock.volume().mean(), mesh.area() * stock.spacing() * stride);
      }
    }
  }
}

// Every one of the 256 cube cases, and many arrangements of them side by side: a stock of
// n × n × n unit cells whose lattice points are emptied one by one with a sphere of radius 0.3
// (it cuts only the three rays through its centre, whose neighbours stand 1 mm away).
TriDexel lattice_pattern(int n, const std::function<bool(int, int, int)>& keep) {
  TriDexel stock = TriDexel::from_box(Aabb{{0, 0, 0}, Vec3::Constant(n)}, 1.0);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        if (keep(i, j, k)) continue;
        const Vec3 center(i + 0.5, j + 0.5, k + 0.5);
        stock.remove(Aabb{center - Vec3::Constant(0.3), center + Vec3::Constant(0.3)},
                     [center](const Ray& ray) { return sphere_chord(ray, center, 0.3); });
      }
    }
  }
  return stock;
}

TEST(DexelMesh, EveryCubeCaseIsClosed) {
  for (int inside = 0; inside < 256; ++inside) {
    const TriDexel stock = lattice_pattern(
        2, [inside](int i, int j, int k) { return ((inside >> (i + 2 * j + 4 * k)) & 1) != 0; });
    const TriangleMesh mesh = dexel_mesh(stock);
    SCOPED_TRACE(testing::Message() << "case " << inside);
    if (inside == 0) {
      EXPECT_TRUE(mesh.empty());
      continue;
    }
    expect_closed_manifold(mesh);
  }
}

// The vertices are numbered in the order the triangles first use them (stock.ply and stock.off
// list them so): walking the triangles, each vertex not met before is the next number.
TEST(DexelMesh, VerticesAreNumberedInTheOrderOfFirstUse) {
  test::Random random(1977);
  for (int trial = 0; trial < 20; ++trial) {
    const TriDexel stock =
        lattice_pattern(4, [&random](int, int, int) { return random.integer(0, 2) != 0; });
    const TriangleMesh mesh = dexel_mesh(stock);
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    int next = 0;
    for (const auto& t : mesh.triangles) {
      for (const int v : t) {
        ASSERT_LE(v, next);
        if (v == next) ++next;
      }
    }
    EXPECT_EQ(next, static_cast<int>(mesh.vertices.size()));
  }
}

TEST(DexelMesh, RandomLatticePatternsAreClosed) {
  test::Random random(2008);
  for (int trial = 0; trial < 60; ++trial) {
    const TriDexel stock =
        lattice_pattern(4, [&random](int, int, int) { return random.integer(0, 1) == 1; });
    const TriangleMesh mesh = dexel_mesh(stock);
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    if (!mesh.empty()) expect_closed_manifold(mesh);
  }
}

// A slotted block of about 400,000 triangles: tens of milliseconds of marching, in which a
// spare thread has time to follow.
TriDexel slotted_block() {
  TriDexel stock = TriDexel::from_box(Aabb{{0, 0, 0}, {40, 30, 10}}, 0.1);
  const Cutter flat = cutter_from_spec("flat:8,20");
  remove_sweep(stock, LinearSweep(flat, Vec3(5, 15, 6), Vec3(35, 15.03, 6), Vec3::UnitZ()));
  return stock;
}

// The mesh made while a follower is handed its triangles is the mesh made without one; the
// follower is handed the first triangles in order, each run with the vertices its triangles
// name, as they end up in the mesh. With one thread nothing is spare and nothing is handed over.
TEST(DexelMesh, AFollowerIsHandedTheFirstTrianglesInOrder) {
  const TriDexel stock = slotted_block();
  const TriangleMesh whole = dexel_mesh(stock);
  ASSERT_GT(whole.triangles.size(), 200'000u);

  tbb::task_arena one(1);
  one.execute([&] {
    const FollowedMesh made =
        dexel_mesh(stock, 1, [](std::span<const std::array<int, 3>>, std::span<const Vec3>) {
          ADD_FAILURE() << "followed on one thread";
        });
    EXPECT_EQ(made.followed, 0u);
    EXPECT_EQ(made.mesh.triangles, whole.triangles);
  });

  // Two threads: the spare one follows once it has started, which on a loaded machine may be
  // late; a few tries make sure it follows at all.
  tbb::task_arena two(2);
  std::size_t followed = 0;
  for (int attempt = 0; attempt < 5 && followed == 0; ++attempt) {
    std::vector<std::array<int, 3>> seen;
    std::vector<Vec3> corners;
    const FollowedMesh made = two.execute([&] {
      return dexel_mesh(
          stock, 1,
          [&](std::span<const std::array<int, 3>> triangles, std::span<const Vec3> vertices) {
            for (const auto& t : triangles) {
              seen.push_back(t);
              for (const int v : t) {
                EXPECT_LT(static_cast<std::size_t>(v), vertices.size());
                corners.push_back(vertices[static_cast<std::size_t>(v)]);
              }
            }
          });
    });
    EXPECT_EQ(made.mesh.triangles, whole.triangles);
    EXPECT_EQ(made.mesh.vertices, whole.vertices);
    ASSERT_EQ(seen.size(), made.followed);
    ASSERT_LE(made.followed, whole.triangles.size());
    EXPECT_TRUE(std::equal(seen.begin(), seen.end(), whole.triangles.begin()));
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const int v = whole.triangles[k / 3][k % 3];
      ASSERT_EQ(corners[k], whole.vertices[static_cast<std::size_t>(v)]) << "corner " << k;
    }
    followed = made.followed;
  }
  EXPECT_GT(followed, 0u) << "the spare thread never followed";
}

// The room reserved for the mesh is counted on all threads, and is the same on any number of them
// (the Z rays' interval ends were once the sum's starting value, counted again for every block of
// layers the reduction made).
TEST(DexelMesh, ItsRoomIsTheSameOnAnyNumberOfThreads) {
  const TriDexel stock = slotted_block();
  std::vector<std::size_t> room;
  for (const int threads : {1, 2, 3}) {
    tbb::task_arena arena(threads);
    const TriangleMesh mesh = arena.execute([&] { return dexel_mesh(stock, 2); });
    room.push_back(mesh.triangles.capacity());
  }
  EXPECT_EQ(room[1], room[0]);
  EXPECT_EQ(room[2], room[0]);
}

// An error in the follower ends the meshing and reaches the caller.
TEST(DexelMesh, AFollowersErrorReachesTheCaller) {
  const TriDexel stock = slotted_block();
  tbb::task_arena two(2);
  bool thrown = false;
  for (int attempt = 0; attempt < 5 && !thrown; ++attempt) {
    try {
      two.execute([&] {
        return dexel_mesh(stock, 1, [](std::span<const std::array<int, 3>>, std::span<const Vec3>) {
          throw InputError("stock.stl: cannot write the file: no space left");
        });
      });
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("no space left"), std::string::npos) << e.what();
      thrown = true;
    }
  }
  EXPECT_TRUE(thrown) << "the spare thread never followed";
}

TEST(DexelMesh, EmptyWorkpieceGivesAnEmptyMesh) {
  TriDexel stock = TriDexel::from_box(Aabb{{0, 0, 0}, {5, 4, 3}}, 0.5);
  Aabb everything = stock.domain();
  everything.inflate(1.0);
  remove_box(stock, everything);
  EXPECT_EQ(stock.volume().mean(), 0.0);
  const TriangleMesh mesh = dexel_mesh(stock);
  EXPECT_TRUE(mesh.empty());
  EXPECT_TRUE(mesh.vertices.empty());
}

// A wall thinner than the spacing that holds one lattice plane (x = 4.75) stands on a 1 mm
// floor: it survives as a wall with its faces exact. One that falls between lattice planes
// (documented behaviour) vanishes and leaves the floor alone.
TEST(DexelMesh, SingleCellThinWall) {
  const Aabb block{{0, 0, 0}, {10, 10, 5}};
  const double s = 0.5;  // lattice planes at x = 0.25, 0.75, …, 4.75, 5.25, …
  const auto carve = [&](double wall_lo, double wall_hi) {
    TriDexel stock = TriDexel::from_box(block, s);
    remove_box(stock, Aabb{{-1, -1, 1}, {wall_lo, 11, 6}});
    remove_box(stock, Aabb{{wall_hi, -1, 1}, {11, 11, 6}});
    return stock;
  };
  // Sharp edges of floor and wall: 4·10 + 4·1 (floor block) + 2·10 + 2·4 + 2·10 (wall rims and
  // roots, both sides) ≈ 92 mm, each missing at most s²/2 per millimetre.
  const double chamfer = 92 * s * s / 2;

  const TriDexel thin = carve(4.6, 4.9);
  const TriangleMesh wall = dexel_mesh(thin);
  expect_closed_manifold(wall);
  EXPECT_NEAR(wall.volume(), 100.0 + 0.3 * 10 * 4, chamfer);
  int on_faces = 0;
  for (const Vec3& v : wall.vertices) {
    if (v.z() > 2 && v.z() < 4 && v.y() > 1 && v.y() < 9) {
      EXPECT_TRUE(std::abs(v.x() - 4.6) < kFloatRounding || std::abs(v.x() - 4.9) < kFloatRounding)
          << v.transpose();
      ++on_faces;
    }
  }
  EXPECT_GT(on_faces, 0);

  const TriangleMesh floor = dexel_mesh(carve(4.8, 5.1));
  expect_closed_manifold(floor);
  EXPECT_NEAR(floor.volume(), 100.0, 44 * s * s / 2);
  EXPECT_LT(floor.bounds().max.z(), 1.0 + kFloatRounding);
}

}  // namespace
}  // namespace cwe
