#include "cwe/io/step.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeAnalysis_ShapeTolerance.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/io/step_shape.hpp"
#include "cwe/workpiece/brep/brep_shapes.hpp"

namespace cwe {
namespace {

// OpenCASCADE prints its translators' messages to standard output by default; the library
// never prints (errors are thrown), so its printers are taken away once.
void quiet_opencascade() {
  static std::once_flag once;
  std::call_once(once, [] {
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

double solid_volume(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props);
  return props.Mass();
}

int count(const TopoDS_Shape& shape, TopAbs_ShapeEnum kind) {
  int n = 0;
  for (TopExp_Explorer e(shape, kind); e.More(); e.Next()) ++n;
  return n;
}

// Welds vertices closer than `tolerance` (a grid of that cell; the nearer of two candidates in
// neighbouring cells wins), so that faces meeting on an edge share its vertices.
class Welder {
 public:
  explicit Welder(double tolerance) : cell_(tolerance) {}
  int add(const Vec3& p, TriangleMesh& mesh) {
    const std::array<long long, 3> key = cell_of(p);
    int best = -1;
    double nearest = cell_ * cell_;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find({key[0] + dx, key[1] + dy, key[2] + dz});
          if (found == cells_.end()) continue;
          for (const int v : found->second) {
            const double d = (mesh.vertices[static_cast<std::size_t>(v)] - p).squaredNorm();
            if (d <= nearest) {
              nearest = d;
              best = v;
            }
          }
        }
      }
    }
    if (best >= 0) return best;
    mesh.vertices.push_back(p);
    const int index = static_cast<int>(mesh.vertices.size()) - 1;
    cells_[key].push_back(index);
    return index;
  }

 private:
  struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const {
      return static_cast<std::size_t>(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
    }
  };
  std::array<long long, 3> cell_of(const Vec3& p) const {
    return {static_cast<long long>(std::floor(p.x() / cell_)),
            static_cast<long long>(std::floor(p.y() / cell_)),
            static_cast<long long>(std::floor(p.z() / cell_))};
  }
  double cell_;
  std::unordered_map<std::array<long long, 3>, std::vector<int>, KeyHash> cells_;
};

// The mesh with only the vertices its triangles use, renumbered in order.
TriangleMesh without_unused_vertices(TriangleMesh mesh) {
  std::vector<int> renumbered(mesh.vertices.size(), -1);
  std::vector<Vec3> used;
  for (std::array<int, 3>& triangle : mesh.triangles) {
    for (int& v : triangle) {
      int& to = renumbered[static_cast<std::size_t>(v)];
      if (to < 0) {
        to = static_cast<int>(used.size());
        used.push_back(mesh.vertices[static_cast<std::size_t>(v)]);
      }
      v = to;
    }
  }
  mesh.vertices = std::move(used);
  return mesh;
}

// The tessellation of one solid that BRepMesh has meshed, its faces joined at their shared
// points; throws ComputationError unless it closes.
TriangleMesh tessellated_part(const TopoDS_Shape& shape, double tolerance, double deviation,
                              const std::string& source) {
  TriangleMesh mesh;
  Welder welder(tolerance);
  // Each face's triangulation nodes as mesh vertices (1-based, as the triangulation's).
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  std::vector<std::vector<int>> node_vertex(static_cast<std::size_t>(faces.Extent()) + 1);
  for (int f = 1; f <= faces.Extent(); ++f) {
    const TopoDS_Face& face = TopoDS::Face(faces(f));
    TopLoc_Location location;
    const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    if (triangulation.IsNull()) {
      throw ComputationError(
          fmt::format("{}: face {} could not be tessellated (BRepMesh left it empty)", source, f));
    }
    const gp_Trsf& move = location.Transformation();
    std::vector<int>& index = node_vertex[static_cast<std::size_t>(f)];
    index.assign(static_cast<std::size_t>(triangulation->NbNodes()) + 1, -1);
    for (int n = 1; n <= triangulation->NbNodes(); ++n) {
      const gp_Pnt p = triangulation->Node(n).Transformed(move);
      index[static_cast<std::size_t>(n)] = welder.add(Vec3(p.X(), p.Y(), p.Z()), mesh);
    }
  }
  // Faces meet on their edges by topology too: BRepMesh discretises each edge once, but every
  // face on it stores the points as its own nodes, and where booleans left the edge and its
  // vertices tolerant the copies lie apart by up to their tolerance (seen: 5.3e-4 mm on a FreeCAD
  // pocket's stock whose edges' largest tolerance was 4.0e-4, the welder's). The k-th point of an
  // edge's polygon on each of its faces is one vertex, where the two copies lie within the
  // deviation of each other (copies farther apart are not the same point: they stay apart, and
  // the closure check below reports them).
  std::vector<int> same(mesh.vertices.size());
  std::iota(same.begin(), same.end(), 0);
  const auto root = [&same](int v) {
    while (same[static_cast<std::size_t>(v)] != v) {
      const int up = same[static_cast<std::size_t>(v)];
      v = same[static_cast<std::size_t>(v)] = same[static_cast<std::size_t>(up)];
    }
    return v;
  };
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  for (int e = 1; e <= edge_faces.Extent(); ++e) {
    const TopoDS_Edge& edge = TopoDS::Edge(edge_faces.FindKey(e));
    std::vector<int> first;  // the edge's points as vertices, from its first face
    for (const TopoDS_Shape& on : edge_faces(e)) {
      const int f = faces.FindIndex(on);
      TopLoc_Location location;
      const Handle(Poly_Triangulation) triangulation =
          BRep_Tool::Triangulation(TopoDS::Face(on), location);
      const Handle(Poly_PolygonOnTriangulation) polygon =
          BRep_Tool::PolygonOnTriangulation(edge, triangulation, location);
      if (polygon.IsNull()) continue;
      const std::vector<int>& index = node_vertex[static_cast<std::size_t>(f)];
      std::vector<int> points;
      for (int k = 1; k <= polygon->NbNodes(); ++k) {
        points.push_back(index[static_cast<std::size_t>(polygon->Node(k))]);
      }
      if (first.empty()) {
        first = std::move(points);
      } else if (points.size() == first.size()) {
        for (std::size_t k = 0; k < points.size(); ++k) {
          const Vec3& pa = mesh.vertices[static_cast<std::size_t>(first[k])];
          const Vec3& pb = mesh.vertices[static_cast<std::size_t>(points[k])];
          if ((pa - pb).norm() > deviation) continue;
          const int a = root(first[k]), b = root(points[k]);
          if (a != b) same[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
        }
      }
    }
  }
  for (std::size_t f = 1; f < node_vertex.size(); ++f) {
    const TopoDS_Face& face = TopoDS::Face(faces(static_cast<int>(f)));
    TopLoc_Location location;
    const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    const std::vector<int>& index = node_vertex[f];
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
      int a = 0, b = 0, c = 0;
      triangulation->Triangle(t).Get(a, b, c);
      if (reversed) std::swap(b, c);
      const std::array<int, 3> tri = {root(index[static_cast<std::size_t>(a)]),
                                      root(index[static_cast<std::size_t>(b)]),
                                      root(index[static_cast<std::size_t>(c)])};
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
      mesh.triangles.push_back(tri);
    }
  }
  // A face narrower than the weld tolerance collapses onto a line, its triangles into folds.
  remove_folds(mesh);
  mesh = without_unused_vertices(std::move(mesh));
  const MeshClosure closure = check_closure(mesh);
  if (!closure.closed()) {
    throw ComputationError(fmt::format(
        "{}: the tessellation at {} mm does not close ({} open, {} non-manifold, {} misoriented "
        "edges of {})",
        source, deviation, closure.boundary_edges, closure.non_manifold_edges,
        closure.misoriented_edges, closure.edges));
  }
  return mesh;
}

}  // namespace

Aabb tight_bounds(const StepModel& model) {
  Bnd_Box box;
  BRepBndLib::AddOptimal(model.impl().shape, box, /*useTriangulation=*/false,
                         /*useShapeTolerance=*/false);
  double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
  box.Get(x0, y0, z0, x1, y1, z1);
  return Aabb{{x0, y0, z0}, {x1, y1, z1}};
}

StepModel step_model(const TopoDS_Shape& shape, const std::string& source,
                     const std::string& unit) {
  auto impl = std::make_shared<StepModel::Impl>();
  double total = 0.0;
  BRep_Builder builder;
  TopoDS_Compound solids;
  builder.MakeCompound(solids);
  std::vector<TopoDS_Solid> found;
  for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) {
    found.push_back(TopoDS::Solid(e.Current()));
  }
  // A solid written as its skin: closed shells that belong to no solid.
  for (TopExp_Explorer e(shape, TopAbs_SHELL, TopAbs_SOLID); e.More(); e.Next()) {
    const TopoDS_Shell& shell = TopoDS::Shell(e.Current());
    if (!BRep_Tool::IsClosed(shell)) continue;
    BRepBuilderAPI_MakeSolid make(shell);
    if (make.IsDone()) found.push_back(make.Solid());
  }
  if (found.empty()) {
    throw InputError(
        SourceLocation{source},
        fmt::format("no solid in the file ({} faces, {} open shells): expected the solid of "
                    "the stock (one solid, or a compound of solids)",
                    count(shape, TopAbs_FACE), count(shape, TopAbs_SHELL)));
  }
  for (std::size_t k = 0; k < found.size(); ++k) {
    TopoDS_Solid solid = found[k];
    if (!BRepCheck_Analyzer(solid).IsValid()) {
      throw InputError(SourceLocation{source},
                       fmt::format("solid {} of {} is not a valid solid (OpenCASCADE's "
                                   "BRepCheck): expected a closed, consistent boundary",
                                   k + 1, found.size()));
    }
    double volume = solid_volume(solid);
    // A shell made solid with its faces inwards bounds the rest of space: turned round.
    if (volume < 0.0) {
      solid.Reverse();
      volume = -volume;
    }
    if (!(volume > 0.0)) {
      throw InputError(SourceLocation{source},
                       fmt::format("solid {} of {} encloses no volume", k + 1, found.size()));
    }
    builder.Add(solids, solid);
    total += volume;
  }
  impl->shape = solids;
  return StepModel(std::move(impl), source, unit, static_cast<int>(found.size()), total);
}

StepModel read_step_file(const std::string& path) {
  quiet_opencascade();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(SourceLocation{path}, "no such file: expected a STEP file (.step, .stp)");
  }
  try {
    // Lengths come out in mm whatever the file's unit.
    STEPControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) {
      throw InputError(SourceLocation{path},
                       "not a readable STEP file (ISO 10303-21): expected a file that starts "
                       "with ISO-10303-21; and holds a DATA section");
    }
    TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
    reader.FileUnits(lengths, angles, solid_angles);
    std::string unit = "millimetre";
    if (lengths.Length() > 0) {
      unit = lengths.Value(1).ToCString();  // "millimetre", "INCH" (a conversion-based unit)…
      std::transform(unit.begin(), unit.end(), unit.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    }
    if (reader.TransferRoots() == 0) {
      throw InputError(SourceLocation{path},
                       "nothing in the file could be translated to a shape: expected the "
                       "solid of the stock");
    }
    return step_model(reader.OneShape(), path, unit);
  } catch (const Standard_Failure& e) {
    throw InputError(SourceLocation{path},
                     fmt::format("OpenCASCADE could not read the file ({}: {})",
                                 e.DynamicType()->Name(), e.GetMessageString()));
  }
}

TriangleMesh tessellate_model(const StepModel& model, double deviation) {
  if (!(deviation > 0.0) || !std::isfinite(deviation)) {
    throw InputError(fmt::format("STEP tessellation: deviation {} mm, expected a positive length",
                                 deviation));
  }
  // BRepMesh stores its triangles on the faces, which copies of a shape share: a deep copy
  // keeps the model as read (shared between threads, tessellated again at another deviation).
  TopoDS_Shape shape;
  try {
    shape = BRepBuilderAPI_Copy(model.impl().shape, /*copyGeom=*/true, /*copyMesh=*/false).Shape();
    BRepMesh_IncrementalMesh mesher(shape, deviation, /*isRelative=*/false,
                                    /*theAngDeflection=*/0.5, /*isInParallel=*/false);
    if (!mesher.IsDone()) throw ComputationError("BRepMesh did not finish");
  } catch (const Standard_Failure& e) {
    throw ComputationError(fmt::format("{}: tessellating the solid failed ({}: {})", model.source(),
                                       e.DynamicType()->Name(), e.GetMessageString()));
  }
  // Faces meet on their edges within the shape's tolerance (a file's often 1e-4 mm or more).
  const double tolerance =
      std::clamp(ShapeAnalysis_ShapeTolerance().Tolerance(shape, 1, TopAbs_EDGE), 1e-7,
                 std::max(1e-7, deviation / 2.0));
  // Each solid is welded and checked on its own, then the solids' meshes are put together: a
  // bull nose round a corner tighter than its radius leaves a spike of stock at the corner's
  // axis that touches the rest along edges only (a solid of its own; four faces on those edges),
  // and one weld over all of them made those edges non-manifold. (A model holds a solid at
  // least: step_model refuses a shape without one.)
  std::vector<TopoDS_Shape> parts;
  for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) parts.push_back(e.Current());
  TriangleMesh whole;
  for (std::size_t part = 0; part < parts.size(); ++part) {
    whole.append(tessellated_part(
        parts[part], tolerance, deviation,
        parts.size() == 1
            ? model.source()
            : fmt::format("{} (solid {} of {})", model.source(), part + 1, parts.size())));
  }
  return whole;
}

std::string step_bytes(const TopoDS_Shape& shape) {
  quiet_opencascade();
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() /
      fmt::format("cwe-step-{}-{}.step", static_cast<long>(::getpid()),
                  reinterpret_cast<std::uintptr_t>(&shape));
  try {
    // Read when the writer makes its model.
    STEPControl_Controller::Init();
    Interface_Static::SetCVal("write.step.unit", "MM");
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    STEPControl_Writer writer;
    if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone) {
      throw ComputationError("STEP output: OpenCASCADE could not translate the solid");
    }
    if (writer.Write(scratch.string().c_str()) != IFSelect_RetDone) {
      std::filesystem::remove(scratch);
      throw ComputationError("STEP output: OpenCASCADE could not write the file");
    }
  } catch (const Standard_Failure& e) {
    std::filesystem::remove(scratch);
    throw ComputationError(fmt::format("STEP output: OpenCASCADE failed ({}: {})",
                                       e.DynamicType()->Name(), e.GetMessageString()));
  }
  std::ifstream in(scratch, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::filesystem::remove(scratch);
  return bytes.str();
}

TriangleMesh tessellate_stock(const BrepStock& stock, double deviation) {
  if (stock.volume() <= 0.0) return TriangleMesh{};  // nothing left
  return tessellate_model(step_model(stock.solid().shape, "the B-rep stock"), deviation);
}

}  // namespace cwe
