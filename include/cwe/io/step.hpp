#pragma once
// STEP files (ISO 10303-21, AP203/AP214/AP242 geometry) read and written with OpenCASCADE: a
// stock from CAD (a casting, a preform, a part with holes) and the in-process workpiece as a
// solid. OpenCASCADE's types stay behind this header (cwe/io/step_shape.hpp hands the shape to
// the B-rep workpiece); docs/stock.md states the reader's rules. The functions declared here work
// in the OpenCASCADE module, loaded when one is first called (cwe/io/occt.hpp).

#include <memory>
#include <string>
#include <string_view>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"

namespace cwe {

// The solids of a STEP file, in millimetres.
class StepModel {
 public:
  // Reads `path`. The file's length unit (SI_UNIT with its prefix, or a CONVERSION_BASED_UNIT
  // such as INCH) is converted to mm. Every solid of the file's root shapes is kept, a
  // compound of solids too; shells that close (a solid written as its skin) are made solids.
  // Throws InputError naming the file: no such file, not STEP, no transferable root, a shape
  // with no solid (only faces, an open shell, wires or points), a solid that is not valid
  // (BRepCheck), or a negative or zero volume.
  static StepModel read(const std::string& path);
  // A model of a shape built in memory (step_model in cwe/io/step_shape.hpp); `source` names
  // it, `unit` is the length unit its file declared.
  struct Impl;  // the shape
  StepModel(std::shared_ptr<const Impl> impl, std::string source, std::string unit, int solids,
            double volume)
      : impl_(std::move(impl)),
        source_(std::move(source)),
        unit_(std::move(unit)),
        solids_(solids),
        volume_(volume) {}

  const std::string& source() const { return source_; }
  int solids() const { return solids_; }
  // The length unit the file declared, as OpenCASCADE names it ("millimetre", "inch", "metre",
  // "foot", …); "millimetre" for a shape built in memory.
  const std::string& file_unit() const { return unit_; }
  double volume() const { return volume_; }  // mm³, exact (of the B-rep)
  Aabb bounds() const;                       // tight (on the surfaces, not the control points)
  // The closed, outward-oriented triangulation of the solids' faces, every triangle within
  // `deviation` mm of its face (BRepMesh's linear deflection, absolute), vertices shared
  // across the faces of a solid; each solid is closed on its own (solids that touch along an
  // edge share no vertex there). Throws ComputationError when a solid's triangulation does not
  // close (a face BRepMesh cannot mesh).
  TriangleMesh tessellate(double deviation) const;

  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<const Impl> impl_;
  std::string source_;
  std::string unit_;
  int solids_ = 0;
  double volume_ = 0.0;  // mm³
};

// True when `path` names a STEP file by its extension (.step, .stp, any case).
bool is_step_path(std::string_view path);

// The B-rep workpiece and STEP: a stock from the model's solids, and the in-process solid as
// STEP bytes (AP214, mm) and as triangles within `deviation` (StepModel::tessellate's rules).
BrepStock brep_stock(const StepModel& model);
// A box (BrepStock::from_box).
BrepStock brep_stock(const Aabb& box);
// The solids a closed triangle mesh bounds (an STL stock on the B-rep workpiece), exact: a
// planar face on each triangle, edges and vertices shared, neighbours in one plane merged into
// one face (ShapeUpgrade_UnifySameDomain); a triangle whose corners lie on a line bounds no
// face, and the face across its longest edge runs through its middle corner. Each
// edge-connected surface bounds a solid; one facing inwards is a cavity of the smallest solid
// that holds it, or, in none, a solid turned inside out (turned round). Throws InputError
// naming `source`: no triangles, a mesh that is not closed (as MeshClosure::problem says), a
// surface inside another that is not a cavity's, surfaces that cross or touch, or a solid
// OpenCASCADE finds invalid; ComputationError if the solids' volume is not the mesh's.
StepModel mesh_solid_model(const TriangleMesh& mesh, const std::string& source);
std::string step_bytes(const BrepStock& stock);
TriangleMesh tessellate(const BrepStock& stock, double deviation);

}  // namespace cwe
