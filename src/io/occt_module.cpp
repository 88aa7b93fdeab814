// The OpenCASCADE module's entry point (cwe/io/occt.hpp): built only into libcwe-occt.so.

#include <cstring>

#include "cwe/engagement/brep_workpiece.hpp"
#include "cwe/io/occt.hpp"
#include "cwe/io/step_shape.hpp"
#include "cwe/workpiece/brep/brep_shapes.hpp"

namespace cwe {
namespace {

class Module final : public OcctModule {
 public:
  StepModel read_step(const std::string& path) const override { return read_step_file(path); }
  Aabb bounds(const StepModel& model) const override { return tight_bounds(model); }
  TriangleMesh tessellate(const StepModel& model, double deviation) const override {
    return tessellate_model(model, deviation);
  }
  StepModel mesh_solid_model(const TriangleMesh& mesh, const std::string& source) const override {
    return mesh_solids(mesh, source);
  }
  BrepStock brep_stock(const StepModel& model) const override {
    return cwe::brep_stock(model.impl().shape);
  }
  BrepStock brep_stock(const Aabb& box) const override { return BrepStock::from_box(box); }
  std::string step_bytes(const BrepStock& stock) const override {
    return cwe::step_bytes(stock.solid().shape);
  }
  TriangleMesh tessellate(const BrepStock& stock, double deviation) const override {
    return tessellate_stock(stock, deviation);
  }
  std::unique_ptr<Workpiece> workpiece(BrepStock& stock, double spacing) const override {
    return std::make_unique<BrepWorkpiece>(stock, spacing);
  }
};

}  // namespace
}  // namespace cwe

extern "C" __attribute__((visibility("default"))) const cwe::OcctModule* cwe_occt_module(
    const char* key) {
  static const cwe::Module module;
  return std::strcmp(key, CWE_OCCT_MODULE_KEY) == 0 ? &module : nullptr;
}
