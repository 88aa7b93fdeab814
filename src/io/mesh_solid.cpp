// The solids a closed triangle mesh bounds, as OpenCASCADE B-rep (an STL stock on the B-rep
// workpiece; cwe/io/step.hpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <BOPAlgo_ArgumentAnalyzer.hxx>
#include <BOPAlgo_CheckResult.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Pln.hxx>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/io/step_shape.hpp"

namespace cwe {
namespace {

gp_Pnt point(const Vec3& p) { return gp_Pnt(p.x(), p.y(), p.z()); }

// A closed surface's faces, a planar face on each triangle, sewn by construction: each vertex
// and edge is made once and shared by the faces on it.
TopoDS_Shell shell_of(const TriangleMesh& part, const SourceLocation& where) {
  const auto corner = [&part](int v) -> const Vec3& {
    return part.vertices[static_cast<std::size_t>(v)];
  };
  std::vector<TopoDS_Vertex> vertices(part.vertices.size());
  const auto vertex = [&](int v) -> const TopoDS_Vertex& {
    TopoDS_Vertex& made = vertices[static_cast<std::size_t>(v)];
    if (made.IsNull()) made = BRepBuilderAPI_MakeVertex(point(corner(v)));
    return made;
  };
  // Each edge once, from its lower vertex index to its higher; a triangle that runs along it
  // the other way takes it reversed.
  std::unordered_map<std::uint64_t, TopoDS_Edge> edges;
  const auto edge = [&](int a, int b) {
    auto [it, inserted] = edges.try_emplace(edge_key(a, b));
    if (inserted) {
      it->second = BRepBuilderAPI_MakeEdge(vertex(std::min(a, b)), vertex(std::max(a, b)));
    }
    return a < b ? it->second : TopoDS::Edge(it->second.Reversed());
  };
  // A triangle whose corners lie on a line (to rounding) has no plane and bounds no face; the
  // face across its longest edge runs along its two short edges instead, through its middle
  // corner (which lies on that edge). Meshes of machined stock have them where a wall's edge is
  // split at a level the other side of it does not share (cwe's own stock.stl).
  std::vector<Vec3> normals(part.triangles.size());
  std::unordered_map<std::uint64_t, int> middle;  // long edge of a flat triangle → its middle
  for (std::size_t t = 0; t < part.triangles.size(); ++t) {
    const auto& v = part.triangles[t];
    normals[t] = (corner(v[1]) - corner(v[0])).cross(corner(v[2]) - corner(v[0]));
    std::size_t longest = 0;  // the edge from v[longest] to v[longest + 1]
    double length = -1.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double l = (corner(v[(k + 1) % 3]) - corner(v[k])).squaredNorm();
      if (l > length) {
        length = l;
        longest = k;
      }
    }
    if (normals[t].norm() > 1e-12 * length) continue;
    normals[t] = Vec3::Zero();
    middle.try_emplace(edge_key(v[longest], v[(longest + 1) % 3]), v[(longest + 2) % 3]);
  }
  // The edges from a to b, through the middles of the flat triangles along it.
  std::vector<TopoDS_Edge> chain;
  const auto along = [&](auto&& self, int a, int b) -> void {
    const auto split = middle.find(edge_key(a, b));
    if (split == middle.end()) {
      chain.push_back(edge(a, b));
      return;
    }
    self(self, a, split->second);
    self(self, split->second, b);
  };
  BRep_Builder builder;
  TopoDS_Shell shell;
  builder.MakeShell(shell);
  for (std::size_t t = 0; t < part.triangles.size(); ++t) {
    if (normals[t] == Vec3::Zero()) continue;
    const auto& v = part.triangles[t];
    chain.clear();
    for (std::size_t k = 0; k < 3; ++k) along(along, v[k], v[(k + 1) % 3]);
    BRepBuilderAPI_MakeWire wire;
    for (const TopoDS_Edge& e : chain) wire.Add(e);
    // The plane's normal along the triangle's: the face faces the way the triangle does, and
    // its wire runs counter-clockwise about it.
    const Vec3& n = normals[t];
    const gp_Pln plane(point(corner(v[0])), gp_Dir(n.x(), n.y(), n.z()));
    std::optional<BRepBuilderAPI_MakeFace> face;
    if (wire.IsDone()) face.emplace(plane, wire.Wire(), /*Inside=*/true);
    if (!face || !face->IsDone()) {
      throw InputError(where, fmt::format("a triangle of the stock mesh at ({:g}, {:g}, {:g}) "
                                          "gives no face",
                                          corner(v[0]).x(), corner(v[0]).y(), corner(v[0]).z()));
    }
    builder.Add(shell, face->Face());
  }
  shell.Closed(true);
  return shell;
}

}  // namespace

StepModel mesh_solids(const TriangleMesh& mesh, const std::string& source) {
  require_closed_stock(mesh, source);
  const SourceLocation where{source};
  // Each edge-connected piece of the mesh is a closed surface of its own.
  const std::vector<TriangleMesh> parts = edge_connected_parts(mesh);
  try {
    BRep_Builder builder;
    std::vector<TopoDS_Shell> shells;
    std::vector<double> enclosed;  // signed: positive where the triangles face outwards
    for (const TriangleMesh& part : parts) {
      shells.push_back(shell_of(part, where));
      enclosed.push_back(part.volume());
    }
    const auto inside_of = [&](std::size_t k) {  // a point of surface k
      const auto& t = parts[k].triangles.front();
      return point((parts[k].vertices[static_cast<std::size_t>(t[0])] +
                    parts[k].vertices[static_cast<std::size_t>(t[1])] +
                    parts[k].vertices[static_cast<std::size_t>(t[2])]) /
                   3.0);
    };
    // A point of a surface lies inside a solid that holds it, not on its boundary (the two
    // surfaces share no edge).
    const auto holds = [](const TopoDS_Solid& solid, const gp_Pnt& p) {
      return BRepClass3d_SolidClassifier(solid, p, 1e-9).State() == TopAbs_IN;
    };
    // A surface facing outwards bounds a solid. One facing inwards is a cavity of the smallest
    // solid that holds it; in none, it is a solid turned inside out and is turned round (the
    // dexel workpiece reads such a mesh as its solid too).
    std::vector<TopoDS_Solid> solids;
    std::vector<double> volumes;
    std::vector<std::size_t> outer;  // each solid's outer surface
    std::vector<std::size_t> cavities;
    for (std::size_t k = 0; k < shells.size(); ++k) {
      if (enclosed[k] < 0.0) {
        cavities.push_back(k);
        continue;
      }
      TopoDS_Solid solid;
      builder.MakeSolid(solid);
      builder.Add(solid, shells[k]);
      solids.push_back(solid);
      volumes.push_back(enclosed[k]);
      outer.push_back(k);
    }
    const std::size_t outward = solids.size();
    double expected = 0.0;
    for (const double v : volumes) expected += v;
    for (const std::size_t k : cavities) {
      const gp_Pnt p = inside_of(k);
      std::size_t holder = outward;
      for (std::size_t s = 0; s < outward; ++s) {
        if (holds(solids[s], p) && (holder == outward || volumes[s] < volumes[holder])) holder = s;
      }
      if (holder < outward) {
        builder.Add(solids[holder], shells[k]);
        expected += enclosed[k];
      } else {
        TopoDS_Solid solid;
        builder.MakeSolid(solid);
        builder.Add(solid, TopoDS::Shell(shells[k].Reversed()));
        solids.push_back(solid);
        volumes.push_back(-enclosed[k]);
        outer.push_back(k);
        expected -= enclosed[k];
      }
    }
    // Solids inside one another would count their common material twice, and the booleans
    // take such a compound wrongly: refused (a surface inside a cavity is a solid of its own).
    for (std::size_t a = 0; a < solids.size(); ++a) {
      for (std::size_t b = 0; b < solids.size(); ++b) {
        if (a == b || volumes[b] > volumes[a]) continue;
        const gp_Pnt p = inside_of(outer[b]);
        if (!holds(solids[a], p)) continue;
        throw InputError(where, fmt::format("the stock mesh has a closed surface inside another "
                                            "at ({:g}, {:g}, {:g}): expected solids apart, a "
                                            "cavity's surface facing into it",
                                            p.X(), p.Y(), p.Z()));
      }
    }
    TopoDS_Compound compound;
    builder.MakeCompound(compound);
    for (const TopoDS_Solid& solid : solids) {
      // Neighbouring triangles in one plane become one face (fewer faces for every boolean).
      ShapeUpgrade_UnifySameDomain unify(solid, /*UnifyEdges=*/true, /*UnifyFaces=*/true,
                                         /*ConcatBSplines=*/false);
      unify.Build();
      builder.Add(compound, unify.Shape());
    }
    // Surfaces that cross or touch, one another's or their own (a self-intersecting mesh):
    // the dexel workpiece takes them by its winding rule, but the booleans would take such a
    // solid wrongly (two overlapping blocks cut by a slot lost nothing).
    BOPAlgo_ArgumentAnalyzer crossing;
    crossing.SetShape1(compound);
    crossing.SelfInterMode() = Standard_True;
    crossing.Perform();
    if (crossing.HasFaulty()) {
      gp_Pnt at;
      for (const BOPAlgo_CheckResult& result : crossing.GetCheckResult()) {
        for (const TopoDS_Shape& faulty : result.GetFaultyShapes1()) {
          TopExp_Explorer first(faulty, TopAbs_VERTEX);
          if (first.More()) at = BRep_Tool::Pnt(TopoDS::Vertex(first.Current()));
        }
      }
      throw InputError(where, fmt::format("the stock mesh's surfaces cross or touch near ({:g}, "
                                          "{:g}, {:g}): expected solids apart and a surface "
                                          "that does not cross itself",
                                          at.X(), at.Y(), at.Z()));
    }
    StepModel model = step_model(compound, source);
    // The faces are the triangles' planes: the solids enclose what the surfaces do, to rounding.
    if (!(std::abs(model.volume() - expected) <= 1e-9 * std::max(1.0, expected))) {
      throw ComputationError(
          fmt::format("{}: the solid of the stock mesh holds {} mm³ where its "
                      "triangles enclose {}",
                      source, model.volume(), expected));
    }
    return model;
  } catch (const Standard_Failure& e) {
    throw InputError(where, fmt::format("OpenCASCADE could not make a solid of the stock mesh: "
                                        "{}",
                                        e.GetMessageString()));
  }
}

}  // namespace cwe
