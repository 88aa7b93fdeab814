// A closed triangle mesh made an exact solid (an STL stock on the B-rep workpiece): volumes,
// faces merged in their planes, cavities, several solids, and the meshes refused.
#include <gtest/gtest.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <GeomAbs_SurfaceType.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Pln.hxx>

#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/io/step.hpp"
#include "cwe/io/step_shape.hpp"
#include "input_error.hpp"
#include "step_fixtures.hpp"

namespace cwe {
namespace {

// A box's 12 triangles facing outwards (inwards with `inward`), appended to `mesh`.
void add_box(TriangleMesh& mesh, const Vec3& lo, const Vec3& hi, bool inward = false) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (int k = 0; k < 8; ++k) {
    mesh.vertices.emplace_back((k & 1) != 0 ? hi.x() : lo.x(), (k & 2) != 0 ? hi.y() : lo.y(),
                               (k & 4) != 0 ? hi.z() : lo.z());
  }
  const std::array<std::array<int, 3>, 12> faces{{{0, 2, 1},
                                                  {1, 2, 3},
                                                  {4, 5, 6},
                                                  {5, 7, 6},
                                                  {0, 1, 4},
                                                  {1, 5, 4},
                                                  {2, 6, 3},
                                                  {3, 6, 7},
                                                  {0, 4, 2},
                                                  {2, 4, 6},
                                                  {1, 3, 5},
                                                  {3, 7, 5}}};
  for (const auto& f : faces) {
    mesh.triangles.push_back(inward ? std::array<int, 3>{base + f[0], base + f[2], base + f[1]}
                                    : std::array<int, 3>{base + f[0], base + f[1], base + f[2]});
  }
}

// Where OpenCASCADE's classifier puts each point against the model's solids.
void expect_states(const StepModel& model,
                   const std::vector<std::pair<gp_Pnt, TopAbs_State>>& expected) {
  for (const auto& [p, state] : expected) {
    BRepClass3d_SolidClassifier classify(model.impl().shape, p, 1e-7);
    EXPECT_EQ(classify.State(), state) << p.X() << ", " << p.Y() << ", " << p.Z();
  }
}

int faces(const StepModel& model) {
  int n = 0;
  for (TopExp_Explorer e(model.impl().shape, TopAbs_FACE); e.More(); e.Next()) ++n;
  return n;
}

TEST(MeshSolid, BoxIsSixFacesOfItsExactVolume) {
  TriangleMesh mesh;
  add_box(mesh, {-1, -1, -1}, {61, 41, 16});
  ASSERT_GT(mesh.volume(), 0.0);
  const StepModel model = mesh_solid_model(mesh, "box.stl");
  EXPECT_EQ(model.solids(), 1);
  EXPECT_EQ(faces(model), 6);  // the two triangles of each side merged
  EXPECT_NEAR(model.volume(), 62.0 * 42.0 * 17.0, 1e-9 * 62.0 * 42.0 * 17.0);
  const Aabb box = model.bounds();
  EXPECT_NEAR((box.min - Vec3(-1, -1, -1)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((box.max - Vec3(61, 41, 16)).norm(), 0.0, 1e-9);
}

TEST(MeshSolid, CavityAndSeparateSolids) {
  // A cavity inside one block, beside a second block of its own.
  TriangleMesh mesh;
  add_box(mesh, {0, 0, 0}, {30, 40, 20});
  add_box(mesh, {10, 10, 5}, {20, 30, 15}, /*inward=*/true);
  add_box(mesh, {35, 0, 0}, {60, 40, 20});
  const StepModel model = mesh_solid_model(mesh, "parts.stl");
  EXPECT_EQ(model.solids(), 2);
  EXPECT_EQ(faces(model), 18);
  const double expected = 30.0 * 40 * 20 - 10.0 * 20 * 10 + 25.0 * 40 * 20;
  EXPECT_NEAR(model.volume(), expected, 1e-9 * expected);
  // The cavity is empty, the blocks' material is not, and the gap between them is not.
  expect_states(model, {{gp_Pnt(15, 20, 10), TopAbs_OUT},
                        {gp_Pnt(5, 20, 10), TopAbs_IN},
                        {gp_Pnt(32, 20, 10), TopAbs_OUT},
                        {gp_Pnt(50, 20, 10), TopAbs_IN}});
}

TEST(MeshSolid, SurfaceFacingInwardsInNoSolidIsTurnedRound) {
  // As the dexel workpiece reads it: the block it bounds. And an island in a cavity is a solid
  // of its own.
  TriangleMesh inverted;
  add_box(inverted, {0, 0, 0}, {2, 3, 4}, /*inward=*/true);
  add_box(inverted, {10, 0, 0}, {20, 10, 10});
  add_box(inverted, {12, 2, 2}, {18, 8, 8}, /*inward=*/true);
  add_box(inverted, {14, 4, 4}, {16, 6, 6});
  const StepModel model = mesh_solid_model(inverted, "inverted.stl");
  EXPECT_EQ(model.solids(), 3);
  const double expected = 24.0 + 1000.0 - 216.0 + 8.0;
  EXPECT_NEAR(model.volume(), expected, 1e-9 * expected);
  expect_states(model, {{gp_Pnt(1, 1, 1), TopAbs_IN},
                        {gp_Pnt(11, 5, 5), TopAbs_IN},
                        {gp_Pnt(13, 5, 5), TopAbs_OUT},
                        {gp_Pnt(15, 5, 5), TopAbs_IN}});
}

TEST(MeshSolid, TrianglesWithTheirCornersOnALineBoundNoFace) {
  // A unit cube whose top edge from (0,0,1) to (1,0,1) is split at its midpoint M on the top's
  // side only: the top's triangle there becomes two, and the triangle (0,0,1), (1,0,1), M closes
  // the surface with no area. Then M is split again, at a quarter, on the same side.
  TriangleMesh flat;
  add_box(flat, {0, 0, 0}, {1, 1, 1});
  auto& top = flat.triangles[2];
  ASSERT_EQ(top, (std::array<int, 3>{4, 5, 6}));
  flat.vertices.emplace_back(0.5, 0.0, 1.0);   // M = 8
  flat.vertices.emplace_back(0.25, 0.0, 1.0);  // Q = 9, between (0,0,1) and M
  top = {4, 9, 6};
  flat.triangles.push_back({9, 8, 6});
  flat.triangles.push_back({8, 5, 6});
  flat.triangles.push_back({4, 5, 8});  // flat: its long edge is the front's
  flat.triangles.push_back({4, 8, 9});  // flat: its long edge 4–8 is the one above's
  ASSERT_TRUE(check_closure(flat).closed());
  const StepModel model = mesh_solid_model(flat, "flat.stl");
  EXPECT_EQ(model.solids(), 1);
  EXPECT_NEAR(model.volume(), 1.0, 1e-12);
  EXPECT_EQ(faces(model), 6);
}

TEST(MeshSolid, TessellatedSolidWithHolesIsItsMeshesVolume) {
  // A STEP solid with two cylindrical holes, tessellated: curved walls give one face per
  // triangle, the flat sides merge. The solid encloses exactly what the triangles do.
  const StepModel original = step_model(test::block_with_holes(), "block");
  const TriangleMesh mesh = original.tessellate(0.01);
  const StepModel model = mesh_solid_model(mesh, "block.stl");
  EXPECT_EQ(model.solids(), 1);
  EXPECT_NEAR(model.volume(), mesh.volume(), 1e-9 * mesh.volume());
  // Within the tessellation's deviation of the exact block: at most 0.01 mm over the walls.
  EXPECT_NEAR(model.volume(), test::kBlockWithHolesVolume, 0.01 * 2.0 * kTwoPi * 5.0 * 20.0);
  // The top and the bottom, of 148 triangles each, are one face each (with the holes' two
  // wires).
  int level_faces = 0;
  for (TopExp_Explorer e(model.impl().shape, TopAbs_FACE); e.More(); e.Next()) {
    const BRepAdaptor_Surface surface(TopoDS::Face(e.Current()));
    ASSERT_EQ(surface.GetType(), GeomAbs_Plane);
    if (std::abs(surface.Plane().Axis().Direction().Z()) > 1.0 - 1e-12) ++level_faces;
  }
  EXPECT_EQ(level_faces, 2);
  std::size_t level_triangles = 0;
  for (const auto& t : mesh.triangles) {
    const auto z = [&](int k) { return mesh.vertices[static_cast<std::size_t>(t[k])].z(); };
    if (z(0) == z(1) && z(1) == z(2)) ++level_triangles;
  }
  EXPECT_GT(level_triangles, 50u);
  // The walls: BRepMesh splits each hole's wall into quads between the top and the bottom,
  // two triangles in one plane, and the block's four sides into two triangles each.
  const int walls = faces(model) - 6;  // less the top, the bottom and the block's four sides
  const auto wall_triangles = static_cast<int>(mesh.triangles.size() - level_triangles) - 8;
  EXPECT_EQ(walls, wall_triangles / 2);
}

TEST(MeshSolid, MeshesThatBoundNoSolidAreRefused) {
  TriangleMesh open;
  add_box(open, {0, 0, 0}, {1, 1, 1});
  open.triangles.pop_back();
  EXPECT_INPUT_ERROR(mesh_solid_model(open, "open.stl");, "not closed: 3 boundary edges");
  // A block inside another, not as a cavity's island.
  TriangleMesh nested;
  add_box(nested, {0, 0, 0}, {10, 10, 10});
  add_box(nested, {2, 2, 2}, {4, 4, 4});
  EXPECT_INPUT_ERROR(mesh_solid_model(nested, "nested.stl");, "closed surface inside another");
  // Two blocks that overlap: as a compound of two solids the booleans took nothing from them.
  TriangleMesh overlapping;
  add_box(overlapping, {0, 0, 0}, {30, 40, 20});
  add_box(overlapping, {20, 0, 0}, {60, 40, 20});
  EXPECT_INPUT_ERROR(mesh_solid_model(overlapping, "overlapping.stl");, "surfaces cross or touch");
  EXPECT_INPUT_ERROR(mesh_solid_model(TriangleMesh{}, "empty.stl");, "no triangles");
}

}  // namespace
}  // namespace cwe
