#pragma once
// OpenCASCADE's side of cwe, STEP files and the B-rep workpiece, is a module of its own
// (libcwe-occt.so), loaded the first time a run needs it. OpenCASCADE's twenty libraries took
// about 70 ms to load and bind, which every process paid, B-rep or not, when cwe linked them.
//
// The functions of cwe/io/step.hpp and brep_workpiece below call into the module; the code
// inside it (cwe/io/step_shape.hpp, cwe/workpiece/brep/, cwe/engagement/brep_workpiece.hpp) is
// built into the module and into the tests that work on OpenCASCADE's shapes themselves
// (the library cwe_occt_impl). Where the module is looked for: $CWE_OCCT_MODULE (a path to
// it), beside the running program (the build folder), in <libdir>/cwe of the installed program
// and of the installed Python package, the folder it is installed to, and the build folder it
// was built in (tests, the Python package in build/python).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cwe/engagement/workpiece.hpp"
#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/io/step.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"

namespace cwe {

// What the module does; the functions of cwe/io/step.hpp say what each means.
class OcctModule {
 public:
  virtual ~OcctModule() = default;
  virtual StepModel read_step(const std::string& path) const = 0;
  virtual Aabb bounds(const StepModel& model) const = 0;
  virtual TriangleMesh tessellate(const StepModel& model, double deviation) const = 0;
  virtual StepModel mesh_solid_model(const TriangleMesh& mesh, const std::string& source) const = 0;
  virtual BrepStock brep_stock(const StepModel& model) const = 0;
  virtual BrepStock brep_stock(const Aabb& box) const = 0;
  virtual std::string step_bytes(const BrepStock& stock) const = 0;
  virtual TriangleMesh tessellate(const BrepStock& stock, double deviation) const = 0;
  virtual std::unique_ptr<Workpiece> workpiece(BrepStock& stock, double spacing) const = 0;
};

// The module, loaded on the first call. Throws ComputationError naming every place looked in
// and why each failed (not found, a module of another build) when it cannot be loaded.
const OcctModule& occt();
// The first module of `paths` that loads and answers this build's key, with the same error.
const OcctModule& load_occt_module(const std::vector<std::filesystem::path>& paths);

// The key a program hands the module's entry point, extern "C" const OcctModule*
// cwe_occt_module(const char* key), which answers only its own (null otherwise): the same version
// of cwe built by the same compiler, since the interface above passes C++ objects. CWE_VERSION
// is defined for the two files that use it (src/io/occt.cpp, src/io/occt_module.cpp).
#define CWE_OCCT_MODULE_KEY ("cwe " CWE_VERSION ", " __VERSION__)

// The B-rep workpiece (BrepWorkpiece) on `stock`, which must outlive it; `spacing` is the
// engagement grid's default disc height (the simulation's resolution).
std::unique_ptr<Workpiece> brep_workpiece(BrepStock& stock, double spacing);

}  // namespace cwe
