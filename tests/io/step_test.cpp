// STEP stock files: solids read in mm from any unit, compounds and skins, errors, and the
// tessellation the dexel and mesh workpieces take. The files are built here with OpenCASCADE.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Pln.hxx>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cwe/core/error.hpp"
#include "cwe/core/numbers.hpp"
#include "cwe/io/step.hpp"
#include "cwe/io/step_shape.hpp"
#include "input_error.hpp"
#include "step_fixtures.hpp"

namespace cwe {
namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "cwe-step-test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

using test::block_with_holes;
constexpr double kBlockVolume = test::kBlockWithHolesVolume;

void write(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The shape written in `unit` ("MM", "INCH", "M") by OpenCASCADE's own writer.
void write_in_unit(const TopoDS_Shape& shape, const char* unit, const std::filesystem::path& path) {
  STEPControl_Controller::Init();
  // Read when the writer makes its model.
  ASSERT_TRUE(Interface_Static::SetCVal("write.step.unit", unit)) << unit;
  STEPControl_Writer writer;
  ASSERT_EQ(writer.Transfer(shape, STEPControl_AsIs), IFSelect_RetDone);
  ASSERT_EQ(writer.Write(path.string().c_str()), IFSelect_RetDone);
  Interface_Static::SetCVal("write.step.unit", "MM");
}

TEST(Step, BlockWithHolesRoundTrips) {
  const auto path = scratch("block.step");
  write(path, step_bytes(block_with_holes()));
  const StepModel model = StepModel::read(path.string());
  EXPECT_EQ(model.solids(), 1);
  EXPECT_EQ(model.file_unit(), "millimetre");
  EXPECT_NEAR(model.volume(), kBlockVolume, 1e-9 * kBlockVolume);
  const Aabb box = model.bounds();
  EXPECT_NEAR((box.min - Vec3(0, 0, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((box.max - Vec3(60, 40, 20)).norm(), 0.0, 1e-6);
}

// The holes' walls become polygons inscribed within the deviation: the mesh holds the solid and
// exceeds it by at most the holes' wall area times the deviation.
TEST(Step, TessellationIsClosedAndWithinItsDeviation) {
  const auto path = scratch("tessellated.step");
  write(path, step_bytes(block_with_holes()));
  const StepModel model = StepModel::read(path.string());
  for (const double deviation : {0.1, 0.01}) {
    SCOPED_TRACE(deviation);
    const TriangleMesh mesh = model.tessellate(deviation);
    EXPECT_TRUE(check_closure(mesh).closed());
    const double walls = 2.0 * kTwoPi * 5.0 * 20.0;
    EXPECT_GE(mesh.volume(), kBlockVolume - 1e-9 * kBlockVolume);
    EXPECT_LE(mesh.volume(), kBlockVolume + walls * deviation);
    // And not far coarser than asked: the chords' sagitta is at least a quarter of it.
    EXPECT_GE(mesh.volume(), kBlockVolume + walls * deviation / 8.0);
  }
}

TEST(Step, InchFileIsReadInMillimetres) {
  const auto path = scratch("inch.step");
  write_in_unit(block_with_holes(), "INCH", path);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_NE(text.find("INCH"), std::string::npos) << "the file is not in inches";
  const StepModel model = StepModel::read(path.string());
  EXPECT_EQ(model.file_unit(), "inch");
  EXPECT_NEAR(model.volume(), kBlockVolume, 1e-6 * kBlockVolume);
  EXPECT_NEAR(model.bounds().max.x(), 60.0, 1e-5);
  // Metres too.
  const auto metres = scratch("metre.step");
  write_in_unit(block_with_holes(), "M", metres);
  const StepModel in_m = StepModel::read(metres.string());
  EXPECT_EQ(in_m.file_unit(), "metre");
  EXPECT_NEAR(in_m.volume(), kBlockVolume, 1e-6 * kBlockVolume);
}

TEST(Step, CompoundOfSolidsAndASolidWrittenAsItsSkin) {
  BRep_Builder builder;
  TopoDS_Compound two;
  builder.MakeCompound(two);
  builder.Add(two, BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10.0, 10.0, 10.0).Shape());
  builder.Add(two, BRepPrimAPI_MakeBox(gp_Pnt(20, 0, 0), 10.0, 5.0, 10.0).Shape());
  const auto path = scratch("two.step");
  write(path, step_bytes(two));
  const StepModel model = StepModel::read(path.string());
  EXPECT_EQ(model.solids(), 2);
  EXPECT_NEAR(model.volume(), 1500.0, 1e-9 * 1500.0);
  EXPECT_NEAR(model.tessellate(0.01).volume(), 1500.0, 1e-9 * 1500.0);
  // The block's closed shell alone (no solid entity): made a solid.
  TopoDS_Shape shell;
  for (TopExp_Explorer e(block_with_holes(), TopAbs_SHELL); e.More(); e.Next()) shell = e.Current();
  const auto skin = scratch("skin.step");
  write(skin, step_bytes(shell));
  const StepModel from_skin = StepModel::read(skin.string());
  EXPECT_EQ(from_skin.solids(), 1);
  EXPECT_NEAR(from_skin.volume(), kBlockVolume, 1e-9 * kBlockVolume);
}

TEST(Step, WhatIsNotASolidIsRefused) {
  const auto missing = scratch("missing.step");
  std::filesystem::remove(missing);
  EXPECT_INPUT_ERROR(StepModel::read(missing.string());, "no such file");
  const auto text = scratch("text.step");
  write(text, "solid cube\nendsolid\n");
  EXPECT_INPUT_ERROR(StepModel::read(text.string());, "not a readable STEP file");
  const auto empty = scratch("empty.stp");
  write(empty, "");
  EXPECT_INPUT_ERROR(StepModel::read(empty.string());, "not a readable STEP file");
  // A face alone, and an open shell (the block's faces but one).
  const auto face = scratch("face.step");
  write(face, step_bytes(BRepBuilderAPI_MakeFace(gp_Pln(gp::XOY()), 0, 10, 0, 10).Face()));
  EXPECT_INPUT_ERROR(StepModel::read(face.string());, "no solid in the file");
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  int n = 0;
  for (TopExp_Explorer e(BRepPrimAPI_MakeBox(10, 10, 10).Shape(), TopAbs_FACE); e.More();
       e.Next()) {
    if (n++ > 0) builder.Add(faces, e.Current());
  }
  const auto open = scratch("open.step");
  write(open, step_bytes(faces));
  EXPECT_INPUT_ERROR(StepModel::read(open.string());, "no solid in the file");
}

TEST(Step, PathsAreToldByTheirExtension) {
  EXPECT_TRUE(is_step_path("a/b/part.step"));
  EXPECT_TRUE(is_step_path("PART.STP"));
  EXPECT_TRUE(is_step_path("x.Step"));
  EXPECT_FALSE(is_step_path("part.stl"));
  EXPECT_FALSE(is_step_path("step"));
  EXPECT_FALSE(is_step_path("part.step.gz"));
}

}  // namespace
}  // namespace cwe
