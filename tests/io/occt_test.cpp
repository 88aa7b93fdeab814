// The OpenCASCADE module (cwe/io/occt.hpp) from a program that does not link OpenCASCADE (this
// test binary): STEP written and read back, a B-rep stock cut through its workpiece, errors
// thrown inside the module caught here, and the loader's refusals.

#include "cwe/io/occt.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "scratch_dir.hpp"

namespace cwe {
namespace {

namespace fs = std::filesystem;

// OpenCASCADE's volume integration and bounding boxes of planar faces are exact up to rounding.
constexpr double kExact = 1e-9;

TEST(OcctModule, StepWrittenAndReadBackWithoutLinkingOpenCascade) {
  const Aabb box{{0.0, 0.0, 0.0}, {40.0, 20.0, 10.0}};
  const BrepStock stock = brep_stock(box);
  EXPECT_NEAR(stock.volume(), 8000.0, 8000.0 * kExact);
  EXPECT_EQ(stock.faces(), 6);

  const fs::path file = test::fresh_scratch_dir("occt-step") / "box.step";
  std::ofstream(file, std::ios::binary) << step_bytes(stock);
  const StepModel model = StepModel::read(file.string());
  EXPECT_EQ(model.source(), file.string());
  EXPECT_EQ(model.solids(), 1);
  EXPECT_EQ(model.file_unit(), "millimetre");
  EXPECT_NEAR(model.volume(), 8000.0, 8000.0 * kExact);
  const Aabb bounds = model.bounds();
  EXPECT_LT((bounds.min - box.min).norm(), 1e-6);
  EXPECT_LT((bounds.max - box.max).norm(), 1e-6);
  // A box's faces are planes: its triangles are the faces themselves, whatever the deviation.
  const TriangleMesh mesh = model.tessellate(0.1);
  EXPECT_NEAR(mesh.volume(), 8000.0, 8000.0 * kExact);
  EXPECT_NEAR(tessellate(stock, 0.1).volume(), 8000.0, 8000.0 * kExact);

  // A stock from the model read, and the STL route (mesh → exact solids).
  EXPECT_NEAR(brep_stock(model).volume(), 8000.0, 8000.0 * kExact);
  EXPECT_NEAR(mesh_solid_model(mesh, "box.stl").volume(), 8000.0, 8000.0 * kExact);
}

TEST(OcctModule, WorkpieceCutsAThroughSlot) {
  // A 10 mm flat end 2 mm deep right through a 40 mm block: a 40 × 10 × 2 slot.
  BrepStock stock = brep_stock(Aabb{{0.0, 0.0, 0.0}, {40.0, 20.0, 10.0}});
  const std::unique_ptr<Workpiece> workpiece = brep_workpiece(stock, 0.1);
  Toolpath path;
  path.sources = {"slot"};
  Move line;
  line.start = Vec3(-10.0, 10.0, 8.0);
  line.end = Vec3(50.0, 10.0, 8.0);
  line.feed_rate = 600.0;
  path.moves = {line};
  const RemovalSummary summary =
      remove_toolpath(*workpiece, cutter_from_spec("flat:10,30"), path, SimulationOptions{});
  ASSERT_EQ(summary.removed_by_move.size(), 1u);
  EXPECT_NEAR(summary.removed_by_move[0], 800.0, 800.0 * 1e-6);
  EXPECT_NEAR(stock.volume(), 7200.0, 7200.0 * 1e-9);
  // The slot adds its floor and two walls, and splits the top in two: 6 - 1 + 2 + 3.
  EXPECT_EQ(stock.faces(), 10);
}

TEST(OcctModule, ErrorsThrownInsideAreCaughtOutside) {
  const fs::path missing = test::fresh_scratch_dir("occt-missing") / "none.step";
  try {
    (void)StepModel::read(missing.string());
    FAIL() << "read a file that is not there";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, missing.string());
    EXPECT_NE(e.message().find("no such file"), std::string::npos) << e.message();
  }
  EXPECT_THROW((void)brep_stock(Aabb{{0.0, 0.0, 0.0}, {1.0, 1.0, 0.0}}), InputError);
  BrepStock cube = brep_stock(Aabb{{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}});
  EXPECT_THROW((void)brep_workpiece(cube, 0.0), InputError);
}

TEST(OcctModule, LoaderNamesEveryPlaceAndWhyItFailed) {
  const fs::path dir = test::fresh_scratch_dir("occt-loader");
  const fs::path missing = dir / "libcwe-occt.so";
  const fs::path not_elf = dir / "text.so";
  std::ofstream(not_elf) << "not a shared object\n";
  // A shared object that loads but is not the module: the maths library.
  const fs::path other = "/lib/x86_64-linux-gnu/libm.so.6";
  try {
    (void)load_occt_module({missing, not_elf, other});
    FAIL() << "loaded a module from nowhere";
  } catch (const ComputationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(missing.string() + " (no such file)"), std::string::npos) << what;
    EXPECT_NE(what.find(not_elf.string() + " ("), std::string::npos) << what;
    if (fs::exists(other)) {
      EXPECT_NE(what.find(other.string() + " (not the module of this build"), std::string::npos)
          << what;
    }
    EXPECT_NE(what.find("CWE_OCCT_MODULE"), std::string::npos) << what;
  }
  // The module itself answers this build, wherever occt() found it.
  EXPECT_NO_THROW((void)load_occt_module({fs::path(CWE_TEST_BUILD_DIR) / "libcwe-occt.so"}));
}

}  // namespace
}  // namespace cwe
