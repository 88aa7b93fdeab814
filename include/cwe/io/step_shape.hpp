#pragma once
// The OpenCASCADE side of StepModel (cwe/io/step.hpp), for the code that works on the shape
// itself (the B-rep workpiece, tests that build solids).

#include <string>

#include <TopoDS_Shape.hxx>

#include "cwe/io/step.hpp"

namespace cwe {

struct StepModel::Impl {
  TopoDS_Shape shape;  // a compound of valid solids of positive volume, mm
};

// A model of the solids of `shape` (mm), checked as StepModel::read checks a file's: closed
// shells are made solids, each solid must be valid and of positive volume. `source` names the
// shape in errors (InputError).
StepModel step_model(const TopoDS_Shape& shape, const std::string& source,
                     const std::string& unit = "millimetre");

// What the functions of cwe/io/step.hpp do, inside the OpenCASCADE module (cwe/io/occt.hpp);
// code in the module calls these, not those.
StepModel read_step_file(const std::string& path);
Aabb tight_bounds(const StepModel& model);
TriangleMesh tessellate_model(const StepModel& model, double deviation);
StepModel mesh_solids(const TriangleMesh& mesh, const std::string& source);
TriangleMesh tessellate_stock(const BrepStock& stock, double deviation);

// `shape` as the bytes of a STEP AP214 file in mm (write them with write_file_atomically or an
// OutputSet). Throws ComputationError when OpenCASCADE cannot translate or write it.
std::string step_bytes(const TopoDS_Shape& shape);

}  // namespace cwe
