#include "cwe/workpiece/brep/brep_shapes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepAlgoAPI_Splitter.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepGProp.hxx>
#include <BRepLib.hxx>
#include <BRepOffsetAPI_MakePipeShell.hxx>
#include <BRepOffsetAPI_ThruSections.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepTools.hxx>
#include <BRepTools_Modification.hxx>
#include <BRepTools_Modifier.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <GProp_GProps.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom2d_Line.hxx>
#include <GeomAPI_Interpolate.hxx>
#include <GeomFill.hxx>
#include <Geom_Circle.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Surface.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <ShapeFix_Shape.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_HArray1OfReal.hxx>
#include <TColgp_HArray1OfPnt.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <gp_Ax3.hxx>
#include <gp_Circ.hxx>
#include <gp_Dir2d.hxx>
#include <gp_Pln.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Trsf.hxx>
#include <gp_Vec2d.hxx>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

gp_Pnt point(const Vec3& p) { return gp_Pnt(p.x(), p.y(), p.z()); }
gp_Dir direction(const Vec3& v) { return gp_Dir(v.x(), v.y(), v.z()); }

// The rigid motion from the tool's frame (tip at the origin, axis along +Z) to the world:
// cwe's tool frame, x as close to world X (or `x_hint`) as the axis allows.
gp_Trsf placement(const Vec3& tip, const Vec3& axis, const Vec3& x_hint = Vec3::UnitX()) {
  const Frame frame = Frame::from_z(tip, axis, x_hint);
  gp_Trsf trsf;
  trsf.SetTransformation(gp_Ax3(point(tip), direction(frame.z()), direction(frame.x())),
                         gp_Ax3(gp::Origin(), gp::DZ(), gp::DX()));
  return trsf;
}

// A surface of revolution whose meridian is a circle in a plane through the axis, its centre off
// the axis, as the torus with the same points: (u, v) on the surface is (u, v + shift) on the
// torus. The torus may be a horn or a spindle one (major radius at or below the minor), as the
// sections of a tool reaching the axis of an arc make. None where the meridian is not such a
// circle.
struct TorusOf {
  Handle(Geom_ToroidalSurface) torus;
  double shift = 0.0;
};

std::optional<TorusOf> torus_of(const Handle(Geom_Surface)& surface) {
  const Handle(Geom_SurfaceOfRevolution) revolution =
      Handle(Geom_SurfaceOfRevolution)::DownCast(surface);
  if (revolution.IsNull()) return std::nullopt;
  Handle(Geom_Curve) meridian = revolution->BasisCurve();
  while (const Handle(Geom_TrimmedCurve) trimmed = Handle(Geom_TrimmedCurve)::DownCast(meridian)) {
    meridian = trimmed->BasisCurve();
  }
  const Handle(Geom_Circle) circle = Handle(Geom_Circle)::DownCast(meridian);
  if (circle.IsNull()) return std::nullopt;
  const gp_Ax1 axis = revolution->Axis();
  const gp_XYZ a = axis.Direction().XYZ(), centre = circle->Location().XYZ();
  const double r = circle->Radius();
  const gp_XYZ foot = axis.Location().XYZ() + ((centre - axis.Location().XYZ()) * a) * a;
  const double big_r = (centre - foot).Modulus();
  // On the axis the meridian makes a sphere, which OpenCASCADE finds.
  if (!(big_r > 1e-7)) return std::nullopt;
  const gp_XYZ x = (centre - foot) / big_r;
  const gp_XYZ xc = circle->XAxis().Direction().XYZ(), yc = circle->YAxis().Direction().XYZ();
  const double alpha = std::atan2(xc * a, xc * x);
  const double sigma = yc * (-std::sin(alpha) * x + std::cos(alpha) * a) > 0.0 ? 1.0 : -1.0;
  gp_Ax3 frame(gp_Pnt(foot), gp_Dir(sigma * a), gp_Dir(x));
  if (sigma < 0.0) frame.YReverse();  // u turns about a either way
  TorusOf result{new Geom_ToroidalSurface(frame, big_r, r), sigma * alpha};
  // The same points, or none (the circle not in a plane through the axis).
  for (const double u : {0.0, 1.1, 2.9}) {
    for (const double v : {0.0, 0.7, 2.3, 4.1}) {
      const gp_Pnt p = revolution->Value(u, v), q = result.torus->Value(u, v + result.shift);
      if (p.Distance(q) > 1e-9 * (big_r + r)) return std::nullopt;
    }
  }
  return result;
}

// The faces whose surface torus_of makes a torus given it, with their curves on it shifted.
// OpenCASCADE's revolve makes a torus of a circle only where the major radius is above the minor
// and the circle's parameter starts at its point farthest from the axis. So the corner of a bull
// nose whose flat radius equals its corner radius (FreeCAD's 6 mm one, corner 1.5: a horn
// torus) and the sections mirrored for an arc's corner were general surfaces of revolution, and
// the straight side after FreeCAD's third corner round a block left an invalid solid. The plane
// through the tool's axis cut such a face along a B-spline, and the straight move's sweep was
// extruded from it. Tori are among OpenCASCADE's analytic surfaces, which it intersects in closed
// form where it can. Every face the tools and their sweeps have on a torus must be one: with the
// tool's tori and the arcs' rings as surfaces of revolution, an arc's pieces cut 2,785 mm³ where
// its motion sweeps 2,789.
class ToriOfRevolution final : public BRepTools_Modification {
 public:
  Standard_Boolean NewSurface(const TopoDS_Face& face, Handle(Geom_Surface)& surface,
                              TopLoc_Location& location, Standard_Real& tolerance,
                              Standard_Boolean& reverse_wires,
                              Standard_Boolean& reverse_face) override {
    const std::optional<TorusOf> torus = torus_of(BRep_Tool::Surface(face, location));
    if (!torus) return false;
    surface = torus->torus;
    tolerance = BRep_Tool::Tolerance(face);
    reverse_wires = false;
    reverse_face = false;
    return true;
  }
  Standard_Boolean NewCurve(const TopoDS_Edge&, Handle(Geom_Curve)&, TopLoc_Location&,
                            Standard_Real&) override {
    return false;
  }
  Standard_Boolean NewPoint(const TopoDS_Vertex&, gp_Pnt&, Standard_Real&) override {
    return false;
  }
  Standard_Boolean NewCurve2d(const TopoDS_Edge& edge, const TopoDS_Face& face, const TopoDS_Edge&,
                              const TopoDS_Face&, Handle(Geom2d_Curve)& curve,
                              Standard_Real& tolerance) override {
    TopLoc_Location location;
    const std::optional<TorusOf> torus = torus_of(BRep_Tool::Surface(face, location));
    if (!torus) return false;
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) old = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (old.IsNull()) return false;
    curve = Handle(Geom2d_Curve)::DownCast(old->Translated(gp_Vec2d(0.0, torus->shift)));
    tolerance = BRep_Tool::Tolerance(edge);
    return true;
  }
  Standard_Boolean NewParameter(const TopoDS_Vertex&, const TopoDS_Edge&, Standard_Real&,
                                Standard_Real&) override {
    return false;
  }
  GeomAbs_Shape Continuity(const TopoDS_Edge& edge, const TopoDS_Face& face1,
                           const TopoDS_Face& face2, const TopoDS_Edge&, const TopoDS_Face&,
                           const TopoDS_Face&) override {
    return BRep_Tool::Continuity(edge, face1, face2);
  }
};

// `shape` with its toroidal surfaces of revolution made tori (ToriOfRevolution).
TopoDS_Shape with_tori(const TopoDS_Shape& shape) {
  bool any = false;
  for (TopExp_Explorer f(shape, TopAbs_FACE); f.More() && !any; f.Next()) {
    any = torus_of(BRep_Tool::Surface(TopoDS::Face(f.Current()))).has_value();
  }
  if (!any) return shape;
  BRepTools_Modifier modifier(shape, new ToriOfRevolution);
  if (!modifier.IsDone()) return shape;
  return modifier.ModifiedShape(shape);
}

void check_done(bool done, const char* what, const Cutter& cutter) {
  if (!done) throw ComputationError(fmt::format("{}: {} failed", cutter.name(), what));
}

// `shape` revolved about `axis` by `angle`, its toroidal faces tori (with_tori): every revolve of
// a tool's section or silhouette goes through here.
TopoDS_Shape revolved(const TopoDS_Shape& shape, const gp_Ax1& axis, double angle, const char* what,
                      const Cutter& cutter, bool copy = false) {
  BRepPrimAPI_MakeRevol revol(shape, axis, angle, copy);
  check_done(revol.IsDone(), what, cutter);
  return with_tori(revol.Shape());
}

// The half of the tool's meridian section at ρ ≥ 0 in its own frame (ρ along X, z along Z),
// from the tip round the profile, across the top and down the axis.
TopoDS_Face meridian_section(const Cutter& cutter) {
  const Profile& profile = cutter.profile();
  const auto xz = [](const Vec2& p) { return gp_Pnt(p.x(), 0.0, p.y()); };
  BRepBuilderAPI_MakeWire wire;
  for (const ProfileSegment& s : profile.segments()) {
    if ((s.end - s.start).norm() < 1e-9) continue;  // a ball's bottom line of length 0
    if (s.kind == ProfileSegment::Kind::kArc) {
      const Handle(Geom_TrimmedCurve) arc =
          GC_MakeArcOfCircle(xz(s.start), xz(s.point_at(0.5)), xz(s.end)).Value();
      wire.Add(BRepBuilderAPI_MakeEdge(arc).Edge());
    } else {
      wire.Add(BRepBuilderAPI_MakeEdge(xz(s.start), xz(s.end)).Edge());
    }
  }
  const Vec2 top(profile.top_radius(), profile.height());
  if (top.x() > 1e-9) wire.Add(BRepBuilderAPI_MakeEdge(xz(top), xz(Vec2(0, top.y()))).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(xz(Vec2(0, top.y())), xz(Vec2(0, 0))).Edge());
  if (!wire.IsDone()) {
    throw ComputationError(
        fmt::format("{}: the profile does not make a closed outline", cutter.name()));
  }
  return BRepBuilderAPI_MakeFace(wire.Wire(), /*OnlyPlane=*/true).Face();
}

// The tool in its own frame: the meridian section revolved about Z.
TopoDS_Solid local_tool(const Cutter& cutter) {
  if (!is_convex(cutter)) {
    throw InputError(SourceLocation{cutter.name()},
                     "the B-rep workpiece sweeps convex cutters (every APT cutter); this "
                     "profile has a concave part");
  }
  TopExp_Explorer solid(revolved(meridian_section(cutter), gp_Ax1(gp::Origin(), gp::DZ()),
                                 2.0 * M_PI, "revolving the profile", cutter),
                        TopAbs_SOLID);
  if (!solid.More()) {
    throw ComputationError(fmt::format("{}: revolving the profile gave no solid", cutter.name()));
  }
  return TopoDS::Solid(solid.Current());
}

struct Plane {
  Vec3 origin, normal;
};

// The sheet that cuts a torus (the corner arc `s` revolved) along its silhouette for a local
// direction d that climbs or descends: n·d = 0 where tan ψ = −(|d_h|/d_z)·cos(θ − β) (ψ the
// angle round the tube, θ round the axis, β d's azimuth), one curve over the half turn of θ
// that faces up the ramp, from the equator through its lowest point back to the equator. The
// sheet is ruled by horizontal segments through that curve, from inside the tube's hole to
// beyond the tool, so it crosses the torus square to the axis's radial direction; its guide
// curves interpolate 129 points of the curve (an error near 1e-9 mm).
TopoDS_Face torus_ramp_sheet(const ProfileSegment& s, const Vec3& d, const Cutter& cutter) {
  const double a = s.center.x(), c = s.center.y(), tube = s.radius;
  const double h = std::hypot(d.x(), d.y()), beta = std::atan2(d.y(), d.x());
  const double from = beta + (d.z() > 0.0 ? -0.5 * M_PI : 0.5 * M_PI);
  const double inner = 0.5 * (a - tube > 0.0 ? a - tube : a), outer = 2.0 * (a + tube) + 1.0;
  constexpr int kPoints = 129;
  Handle(TColgp_HArray1OfPnt) near = new TColgp_HArray1OfPnt(1, kPoints);
  Handle(TColgp_HArray1OfPnt) far = new TColgp_HArray1OfPnt(1, kPoints);
  Handle(TColStd_HArray1OfReal) params = new TColStd_HArray1OfReal(1, kPoints);
  const double lo = std::min(s.start_angle(), s.end_angle()),
               hi = std::max(s.start_angle(), s.end_angle());
  for (int k = 0; k < kPoints; ++k) {
    const double theta = from + M_PI * k / (kPoints - 1);
    const double psi = std::atan(-(h / d.z()) * std::cos(theta - beta));
    if (psi < lo - 1e-12 || psi > hi + 1e-12) {
      throw ComputationError(
          fmt::format("{}: the silhouette leaves the corner arc's torus along this ramp (the B-rep "
                      "workpiece sweeps corner arcs that run from the bottom to the equator)",
                      cutter.name()));
    }
    const double z = c + tube * std::sin(psi);
    near->SetValue(k + 1, gp_Pnt(inner * std::cos(theta), inner * std::sin(theta), z));
    far->SetValue(k + 1, gp_Pnt(outer * std::cos(theta), outer * std::sin(theta), z));
    params->SetValue(k + 1, theta);
  }
  GeomAPI_Interpolate near_curve(near, params, false, 1e-12), far_curve(far, params, false, 1e-12);
  near_curve.Perform();
  far_curve.Perform();
  check_done(near_curve.IsDone() && far_curve.IsDone(), "the torus's silhouette curve", cutter);
  const Handle(Geom_Surface) ruled = GeomFill::Surface(near_curve.Curve(), far_curve.Curve());
  return BRepBuilderAPI_MakeFace(ruled, 1e-9).Face();
}

// The planes that cut the tool's faces along its silhouette for local direction d (see the
// header): the plane through the axis square to d's horizontal part (it also halves the discs a
// level move grazes), a sphere's plane through its centre square to d, a cone's plane through
// its apex and rulings, a torus's equator under a plunge.
std::vector<Plane> silhouette_planes(const Cutter& cutter, const Vec3& d,
                                     std::vector<TopoDS_Face>& sheets) {
  const double length = d.norm();
  const double eps = 1e-12 * length;
  const Vec3 dh(d.x(), d.y(), 0.0);
  const double h = dh.norm();
  const bool climbs = std::abs(d.z()) > eps, across = h > eps;
  std::vector<Plane> planes;
  if (across) planes.push_back({Vec3::Zero(), Vec3(dh / h)});
  for (const ProfileSegment& s : cutter.profile().segments()) {
    if ((s.end - s.start).norm() < 1e-9) continue;
    if (s.kind == ProfileSegment::Kind::kLine) {
      if (s.is_horizontal() || s.is_vertical() || !across) continue;
      // A cone: rulings at azimuth ψ0 ± θ, cos θ = −n_z d_z / (n_ρ |d_h|), through the apex.
      const Vec2 n = s.normal_at(0.0);
      const double c = -n.y() * d.z() / (n.x() * h);
      if (!(std::abs(c) < 1.0 - 1e-12)) continue;  // wholly leading or trailing
      const double theta = std::acos(c), psi = std::atan2(dh.y(), dh.x());
      const Vec2 a = s.start, b = s.end;
      const Vec3 apex(0.0, 0.0, a.y() - a.x() * (b.y() - a.y()) / (b.x() - a.x()));
      const Vec2 far = b.x() > a.x() ? b : a;
      const Vec3 p(far.x() * std::cos(psi + theta), far.x() * std::sin(psi + theta), far.y());
      const Vec3 q(far.x() * std::cos(psi - theta), far.x() * std::sin(psi - theta), far.y());
      planes.push_back({apex, (p - apex).cross(q - apex).normalized()});
    } else if (std::abs(s.center.x()) < 1e-9) {  // a sphere: its great circle square to d
      planes.push_back({Vec3(0.0, 0.0, s.center.y()), d / length});
    } else if (!climbs) {  // a torus, d square to the axis: the axial plane
    } else if (!across) {  // a torus, d along the axis: its equator, where the arc holds it
      const double z = s.center.y();
      if (z > s.min_z() + 1e-9 && z < s.max_z() - 1e-9) {
        planes.push_back({Vec3(0.0, 0.0, z), Vec3::UnitZ()});
      }
    } else {
      sheets.push_back(torus_ramp_sheet(s, d, cutter));
    }
  }
  // One of each plane.
  std::vector<Plane> unique;
  for (const Plane& p : planes) {
    const bool seen = std::any_of(unique.begin(), unique.end(), [&](const Plane& q) {
      return std::abs(std::abs(p.normal.dot(q.normal)) - 1.0) < 1e-12 &&
             std::abs((p.origin - q.origin).dot(q.normal)) < 1e-9;
    });
    if (!seen) unique.push_back(p);
  }
  return unique;
}

// A point inside the face and its outward normal there.
bool face_sample(const TopoDS_Face& face, Vec3& at, Vec3& normal) {
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  const BRepAdaptor_Surface surface(face);
  // The middle of the face's parameter box first, then ever finer grids over it (a sliver
  // between two cuts may hold none of the coarse points).
  for (int grid = 1; grid <= 64; grid *= 2) {
    for (int i = 0; i < grid; ++i) {
      for (int j = 0; j < grid; ++j) {
        const double fu = (i + 0.5) / grid, fv = (j + 0.5) / grid;
        const gp_Pnt2d uv(u0 + fu * (u1 - u0), v0 + fv * (v1 - v0));
        BRepClass_FaceClassifier inside(face, uv, 1e-9);
        if (inside.State() != TopAbs_IN) continue;
        gp_Pnt p;
        gp_Vec du, dv;
        surface.D1(uv.X(), uv.Y(), p, du, dv);
        gp_Vec n = du.Crossed(dv);
        if (n.Magnitude() < 1e-12) continue;
        if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
        n.Normalize();
        at = Vec3(p.X(), p.Y(), p.Z());
        normal = Vec3(n.X(), n.Y(), n.Z());
        return true;
      }
    }
  }
  return false;
}

// A swept solid whose volume is not the one its motion sweeps (OpenCASCADE's booleans can lose
// part of a solid without a word) is refused.
void check_volume(const TopoDS_Shape& swept, double expected, const Cutter& cutter,
                  const char* what) {
  const double v = shape_volume(swept);
  if (!(std::abs(v - expected) <= 1e-5 * expected)) {
    throw ComputationError(
        fmt::format("{}: the {} has a volume of {:.6g} mm³ where the motion sweeps {:.6g} mm³",
                    cutter.name(), what, v, expected));
  }
}
}  // namespace

double shape_volume(const TopoDS_Shape& shape) {
  // The faces to integrate: each face, but for a planar face of several wires the face of each
  // wire alone, oriented as the face for its outer wire and against it for a hole.
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  bool split = false;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face& face = TopoDS::Face(e.Current());
    int wires = 0;
    for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next()) ++wires;
    if (wires < 2) {  // most faces: no surface looked at
      builder.Add(faces, face);
      continue;
    }
    const BRepAdaptor_Surface surface(face, /*restriction=*/false);
    if (surface.GetType() != GeomAbs_Plane) {
      builder.Add(faces, face);
      continue;
    }
    const TopoDS_Wire outer = BRepTools::OuterWire(face);
    std::vector<TopoDS_Face> parts;
    for (TopExp_Explorer w(face.Oriented(TopAbs_FORWARD), TopAbs_WIRE); w.More(); w.Next()) {
      const TopoDS_Wire& wire = TopoDS::Wire(w.Current());
      BRepBuilderAPI_MakeFace make(surface.Plane(), wire, /*Inside=*/true);
      if (!make.IsDone()) break;
      // The face of a wire alone is the region it encloses, on the plane's side.
      TopoDS_Face part = make.Face();
      if (!wire.IsSame(outer)) part.Reverse();
      if (face.Orientation() == TopAbs_REVERSED) part.Reverse();
      parts.push_back(part);
    }
    if (outer.IsNull() || static_cast<int>(parts.size()) < wires) {
      builder.Add(faces, face);  // a wire no face can be made of: the face's own integral
      continue;
    }
    for (const TopoDS_Face& part : parts) builder.Add(faces, part);
    split = true;
  }
  GProp_GProps props;
  BRepGProp::VolumeProperties(split ? TopoDS_Shape(faces) : shape, props);
  return props.Mass();
}

void run_boolean(BRepAlgoAPI_BooleanOperation& op, const TopoDS_Shape& argument,
                 const TopoDS_Shape& tool, double fuzzy) {
  TopTools_ListOfShape arguments, tools;
  arguments.Append(argument);
  tools.Append(tool);
  op.SetArguments(arguments);
  op.SetTools(tools);
  op.SetRunParallel(false);
  // Without it OpenCASCADE may raise the tolerances of the arguments' own edges and vertices
  // while it intersects them, also on an attempt that is then refused: the stock kept as it was
  // before a refused cut is no longer what it was.
  op.SetNonDestructive(true);
  if (fuzzy > 0.0) op.SetFuzzyValue(fuzzy);
  op.Build();
}

TopoDS_Shape mended_copy(const TopoDS_Shape& shape) {
  Handle(ShapeFix_Shape) fix = new ShapeFix_Shape(BRepBuilderAPI_Copy(shape).Shape());
  fix->Perform();
  return fix->Shape();
}

TopoDS_Solid tool_solid(const Cutter& cutter, const Vec3& tip, const Vec3& axis) {
  try {
    const TopoDS_Shape placed =
        BRepBuilderAPI_Transform(local_tool(cutter), placement(tip, axis), true).Shape();
    return TopoDS::Solid(placed);
  } catch (const Standard_Failure& e) {
    throw ComputationError(fmt::format("{}: OpenCASCADE could not build the tool ({})",
                                       cutter.name(), e.GetMessageString()));
  }
}

namespace {

// Whether a face of the tool (a point inside it and its outward normal, in the tool's frame)
// trails under a translation along local d: by the sign of n·d; a face d runs along (a disc
// under a level move, the flank under a plunge) by its side of the axial plane, or trailing
// under a plunge.
struct Trailing {
  Vec3 d;
  bool operator()(const Vec3& at, const Vec3& normal) const {
    const Vec3 dh(d.x(), d.y(), 0.0);
    const bool across = dh.norm() > 1e-12 * d.norm();
    const double lead = normal.dot(d) / d.norm();
    return std::abs(lead) > 1e-9 ? lead < 0.0 : !across || at.dot(dh) < 0.0;
  }
};

// The tool's faces (`tool`, a solid) cut by the planes.
TopoDS_Shape cut_faces(const TopoDS_Shape& tool, const std::vector<Plane>& planes, double big,
                       const Cutter& cutter, const std::vector<TopoDS_Face>& sheets = {}) {
  if (planes.empty() && sheets.empty()) return tool;
  TopTools_ListOfShape skin, cuts;
  for (TopExp_Explorer e(tool, TopAbs_SHELL); e.More(); e.Next()) skin.Append(e.Current());
  for (const TopoDS_Face& sheet : sheets) cuts.Append(sheet);
  for (const Plane& plane : planes) {
    cuts.Append(BRepBuilderAPI_MakeFace(gp_Pln(point(plane.origin), direction(plane.normal)), -big,
                                        big, -big, big)
                    .Face());
  }
  BRepAlgoAPI_Splitter splitter;
  splitter.SetArguments(skin);
  splitter.SetTools(cuts);
  splitter.SetRunParallel(false);
  splitter.Build();
  check_done(splitter.IsDone() && !splitter.HasErrors(), "cutting the tool's faces", cutter);
  return splitter.Shape();
}

// The faces added to `sewing`, sewn into a valid solid. Throws ComputationError when they do
// not close into one.
TopoDS_Solid sewn_solid(BRepBuilderAPI_Sewing& sewing, const Cutter& cutter) {
  sewing.Perform();
  TopoDS_Shell shell;
  int shells = 0;
  for (TopExp_Explorer e(sewing.SewedShape(), TopAbs_SHELL); e.More(); e.Next()) {
    shell = TopoDS::Shell(e.Current());
    ++shells;
  }
  if (shells != 1 || !BRep_Tool::IsClosed(shell)) {
    throw ComputationError(
        fmt::format("{}: the swept volume's faces do not close into one skin ({} shells)",
                    cutter.name(), shells));
  }
  BRepBuilderAPI_MakeSolid make(shell);
  check_done(make.IsDone(), "making the swept volume a solid", cutter);
  TopoDS_Solid solid = make.Solid();
  if (shape_volume(solid) < 0.0) solid.Reverse();
  if (!BRepCheck_Analyzer(solid).IsValid()) {
    throw ComputationError(fmt::format("{}: the swept volume is not a valid solid", cutter.name()));
  }
  return solid;
}

// The tool's faces (cut along the silhouette) sorted by `trails(point, outward normal)`, and
// the silhouette: the edges between a trailing face and a leading one.
struct Sides {
  std::vector<TopoDS_Face> trailing, leading;
  std::vector<TopoDS_Edge> silhouette;
};

template <class Trails>
Sides sides(const TopoDS_Shape& faces, Trails trails, const Cutter& cutter) {
  Sides out;
  TopTools_IndexedMapOfShape trailing;
  for (TopExp_Explorer e(faces, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face& face = TopoDS::Face(e.Current());
    Vec3 at = Vec3::Zero(), normal = Vec3::Zero();
    if (!face_sample(face, at, normal)) {
      throw ComputationError(
          fmt::format("{}: a face of the tool has no inner point", cutter.name()));
    }
    const bool trail = trails(at, normal);
    if (trail) trailing.Add(face);
    (trail ? out.trailing : out.leading).push_back(face);
  }
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndAncestors(faces, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  for (int k = 1; k <= edge_faces.Extent(); ++k) {
    const TopoDS_Edge& edge = TopoDS::Edge(edge_faces.FindKey(k));
    if (BRep_Tool::Degenerated(edge)) continue;
    int trail = 0, lead = 0;
    for (const TopoDS_Shape& f : edge_faces.FindFromIndex(k))
      ++(trailing.Contains(f) ? trail : lead);
    if (trail > 0 && lead > 0) out.silhouette.push_back(edge);
  }
  return out;
}

// The solid a tool sweeps under a rigid motion, sewn from its faces (`faces`: the tool's faces
// cut along the silhouette): those for which `trails(point, outward normal)` holds kept where
// the motion starts, the others moved to where it ends by `to_end`, and the silhouette (edges
// between the two kinds) swept by `band`. Throws ComputationError when the faces do not close
// into a valid solid.
template <class Trails, class Band>
TopoDS_Shape sewn_sweep(const TopoDS_Shape& faces, Trails trails, const gp_Trsf& to_end, Band band,
                        double tolerance, const Cutter& cutter) {
  const Sides sorted = sides(faces, trails, cutter);
  BRepBuilderAPI_Sewing sewing(tolerance);
  for (const TopoDS_Face& face : sorted.trailing) sewing.Add(face);
  for (const TopoDS_Face& face : sorted.leading) {
    sewing.Add(BRepBuilderAPI_Transform(face, to_end, true).Shape());
  }
  for (const TopoDS_Edge& edge : sorted.silhouette) sewing.Add(band(edge));
  return sewn_solid(sewing, cutter);
}

}  // namespace

TopoDS_Shape linear_sweep_solid(const Cutter& cutter, const Vec3& start, const Vec3& end,
                                const Vec3& axis) {
  try {
    const gp_Trsf to_world = placement(start, axis);
    const TopoDS_Solid tool = local_tool(cutter);
    const Frame frame = Frame::from_z(start, axis, Vec3::UnitX());
    const Vec3 d = frame.direction_to_local(end - start);
    const double reach = std::hypot(cutter.profile().max_radius(), cutter.profile().height());
    if (!(d.norm() > 1e-9 * reach)) {
      return BRepBuilderAPI_Transform(tool, to_world, true).Shape();
    }
    std::vector<TopoDS_Face> sheets;
    const std::vector<Plane> planes = silhouette_planes(cutter, d, sheets);
    const TopoDS_Shape faces = cut_faces(tool, planes, 4.0 * reach, cutter, sheets);
    const Trailing trails{d};
    const gp_Vec along(d.x(), d.y(), d.z());
    gp_Trsf shift;
    shift.SetTranslation(along);
    const auto band = [&](const TopoDS_Edge& edge) {
      BRepPrimAPI_MakePrism prism(edge, along, /*Copy=*/true);
      check_done(prism.IsDone(), "sweeping the silhouette", cutter);
      return prism.Shape();
    };
    const TopoDS_Shape swept = sewn_sweep(faces, trails, shift, band, 1e-6 * reach, cutter);
    check_volume(swept, line_swept_volume(cutter, d), cutter, "line's swept volume");
    return BRepBuilderAPI_Transform(swept, to_world, true).Shape();
  } catch (const Standard_Failure& e) {
    throw ComputationError(fmt::format("{}: OpenCASCADE could not build the swept volume ({})",
                                       cutter.name(), e.GetMessageString()));
  }
}

namespace {

// The tool's meridian section in the plane through its axis and the arc's, on the tool's side of
// the arc's axis: the profile's half sections on both sides of the tool's axis, the one towards
// the arc's axis cut at it (`big_r` from the tool's axis along unit `radial`), made from the
// profile's exact lines and circles. The section the placed tool and a half-plane had in common
// (OpenCASCADE's intersection curves) made rings whose sweeps were refused or never finished
// their check where the arc's axis meets the tool's side or corner: FreeCAD's profile round a
// block's corners, arcs of the tool's radius, fell back to linear pieces or hung. Made so, the
// corners of FreeCAD's two-tool program are cut exactly in 1 to 7 s each.
TopoDS_Shape arc_section(const Cutter& cutter, const Vec3& tip, const Vec3& axis,
                         const Vec3& radial, double big_r) {
  const TopoDS_Face half = meridian_section(cutter);
  gp_Trsf mirror;
  mirror.SetMirror(gp_Ax2(gp::Origin(), gp::DX()));
  TopoDS_Shape towards = BRepBuilderAPI_Transform(half, mirror, true).Shape();
  const double rho = cutter.profile().max_radius(), height = cutter.profile().height();
  if (big_r < rho) {
    // The plane y = 0, u along x and v along −z.
    const gp_Pln xz(gp_Ax3(gp::Origin(), gp::DY(), gp::DX()));
    const TopoDS_Face keep =
        BRepBuilderAPI_MakeFace(xz, -big_r, 0.0, -height - 1.0, 1.0).Face();
    BRepAlgoAPI_Common cut(towards, keep);
    check_done(cut.IsDone() && !cut.HasErrors(), "the tool's section at the arc's axis", cutter);
    towards = cut.Shape();
  }
  BRepAlgoAPI_Fuse both(half, towards);
  check_done(both.IsDone() && !both.HasErrors(), "the tool's section", cutter);
  ShapeUpgrade_UnifySameDomain one(both.Shape(), true, true, true);
  one.Build();
  return BRepBuilderAPI_Transform(one.Shape(), placement(tip, axis, radial), true).Shape();
}

}  // namespace

std::vector<TopoDS_Shape> planar_arc_sweep_solids(const Cutter& cutter, const Move& arc) {
  try {
    const Vec3 axis = arc.start_axis.normalized();
    const Vec3 normal = arc.normal.normalized();
    const Vec3 radial = arc.start - arc.center - (arc.start - arc.center).dot(normal) * normal;
    const double big_r = radial.norm();
    const TopoDS_Solid start = tool_solid(cutter, arc.start, axis);
    if (!(big_r > 1e-9)) return {start};  // the tool turning on its own axis
    const double rho = cutter.profile().max_radius();
    const double reach = std::hypot(rho, cutter.profile().height());
    const double big = 4.0 * (reach + big_r);
    const gp_Ax1 arc_axis(point(arc.center), direction(normal));
    const double angle = std::min(arc.sweep, 2.0 * M_PI);
    // The direction of travel at the tip, and the plane through both axes.
    const Vec3 travel = normal.cross(radial).normalized();
    if (big_r > rho + 1e-6 * reach && angle < 2.0 * M_PI) {
      // Off the arc's axis: sewn from the tool's faces cut by the plane through both axes, where
      // its silhouette lies (n is square to ω × (p − C) there); the faces the arc runs along
      // (discs) by their side of that plane.
      const TopoDS_Shape faces = cut_faces(start, {{arc.start, travel}}, big, cutter);
      const Vec3 centre = arc.center;
      const auto trails = [&](const Vec3& at, const Vec3& n) {
        const Vec3 velocity = normal.cross(at - centre);
        const double lead = n.dot(velocity) / velocity.norm();
        return std::abs(lead) > 1e-9 ? lead < 0.0 : (at - arc.start).dot(travel) < 0.0;
      };
      gp_Trsf turn;
      turn.SetRotation(arc_axis, angle);
      const auto band = [&](const TopoDS_Edge& edge) {
        return revolved(edge, arc_axis, angle, "revolving the silhouette", cutter, /*copy=*/true);
      };
      const TopoDS_Shape swept = sewn_sweep(faces, trails, turn, band, 1e-6 * reach, cutter);
      check_volume(swept, planar_arc_swept_volume(cutter, big_r, angle), cutter,
                   "arc's swept volume");
      return {swept};
    }
    // A full circle, or a corner (the tool covers the arc's axis): the section on the tool's
    // side of the arc's axis (arc_section), revolved, and the tool at both ends.
    const TopoDS_Shape ring_solid =
        revolved(arc_section(cutter, arc.start, axis, radial / big_r, big_r), arc_axis, angle,
                 "revolving the tool's section", cutter);
    // A solid of revolution's volume is proportional to its angle (Pappus): the ring's is the full
    // circle's sweep's share.
    check_volume(ring_solid,
                 planar_arc_swept_volume(cutter, big_r, 2.0 * M_PI) * angle / (2.0 * M_PI), cutter,
                 "revolved section");
    if (angle >= 2.0 * M_PI) return {ring_solid};
    // The pieces are cut one after the other, and their union's volume is checked as what they
    // cut, in that order, from a block holding them (with a fuzzy value of 1e-6 of the block's
    // size, the rule the stock's cuts take first). OpenCASCADE gets some orders wrong, the
    // ring's end sections lying on the tools' surfaces. The ring first cut a bull nose's end
    // tool as nothing. The ring last cut a 10 mm bull nose's (corner 2) round an arc of radius
    // 4, whose ring reaches across the arc's axis, 2.3e-5 short of its motion's sweep, where the
    // motion's order (start, ring, end) cut it to 3e-7. Without the fuzzy value, the ring last
    // took 23 s for a 6 mm bull nose round a corner at its radius, and the other orders were
    // 2e-6 short. So the orders in turn, the first whose cut is what the motion sweeps.
    const TopoDS_Solid end = tool_solid(cutter, arc.end, axis);
    const std::vector<TopoDS_Shape> orders[] = {
        {start, end, ring_solid}, {start, ring_solid, end}, {ring_solid, start, end}};
    Bnd_Box bounds;
    for (const TopoDS_Shape& piece : orders[0]) BRepBndLib::Add(piece, bounds, false);
    bounds.Enlarge(1.0);
    double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
    bounds.Get(x0, y0, z0, x1, y1, z1);
    const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape();
    const double full = shape_volume(box);
    const double expected = planar_arc_swept_volume(cutter, big_r, angle);
    std::string cuts;
    for (const std::vector<TopoDS_Shape>& pieces : orders) {
      cuts += cuts.empty() ? "" : ", ";
      try {
        TopoDS_Shape block = box;
        bool done = true;
        for (const TopoDS_Shape& piece : pieces) {
          BRepAlgoAPI_Cut cut;
          run_boolean(cut, block, piece, 1e-6 * std::sqrt(bounds.SquareExtent()));
          done = cut.IsDone() && !cut.HasErrors();
          if (!done) break;
          block = cut.Shape();
        }
        if (!done) {
          cuts += "an error";
          continue;
        }
        const double swept = full - shape_volume(block);
        const bool valid = BRepCheck_Analyzer(block).IsValid();
        if (valid && std::abs(swept - expected) <= 1e-5 * expected) return pieces;
        cuts += fmt::format("{:.6g}{}", swept, valid ? "" : " (an invalid solid)");
      } catch (const Standard_Failure& e) {
        cuts += fmt::format("an error ({})", e.GetMessageString());
      }
    }
    throw ComputationError(fmt::format(
        "{}: the arc's pieces cut from a block (in three orders): {} mm³, where the motion "
        "sweeps {:.6g} mm³",
        cutter.name(), cuts, expected));
  } catch (const Standard_Failure& e) {
    throw ComputationError(fmt::format("{}: OpenCASCADE could not build the arc's sweep ({})",
                                       cutter.name(), e.GetMessageString()));
  }
}

namespace {

// The turn by `angle` about the line through `centre` along unit `normal`, then the rise along
// it.
// A direction moved by a rigid motion.
Vec3 turned(const gp_Trsf& motion, const Vec3& v) {
  const gp_Vec w = gp_Vec(v.x(), v.y(), v.z()).Transformed(motion);
  return Vec3(w.X(), w.Y(), w.Z());
}

gp_Trsf screw_motion(const Vec3& centre, const Vec3& normal, double angle, double rise) {
  gp_Trsf turn, lift;
  turn.SetRotation(gp_Ax1(point(centre), direction(normal)), angle);
  lift.SetTranslation(gp_Vec(rise * normal.x(), rise * normal.y(), rise * normal.z()));
  return lift.Multiplied(turn);
}

// The face a straight edge along unit `normal` sweeps under the screw about the line through
// `centre` along `normal` by `angle` and `rise`: a piece of the cylinder about that line, bounded
// by the edge, its screwed copy and the two helices their ends trace (lines in the cylinder's
// (angle, height)). None for an edge that is not such a segment, or lies on the axis.
std::optional<TopoDS_Face> screwed_ruling(const TopoDS_Edge& edge, const Vec3& centre,
                                          const Vec3& normal, double angle, double rise) {
  const BRepAdaptor_Curve curve(edge);
  if (curve.GetType() != GeomAbs_Line) return std::nullopt;
  const gp_Pnt a = curve.Value(curve.FirstParameter()), b = curve.Value(curve.LastParameter());
  const Vec3 pa(a.X(), a.Y(), a.Z()), pb(b.X(), b.Y(), b.Z());
  const Vec3 along = pb - pa;
  if (!(along.norm() > 0.0) || along.normalized().cross(normal).norm() > 1e-12) {
    return std::nullopt;
  }
  const Vec3 offset = pa - centre - (pa - centre).dot(normal) * normal;
  if (!(offset.norm() > 1e-9)) return std::nullopt;
  const gp_Ax3 frame(point(centre), direction(normal), direction(offset));
  const Handle(Geom_CylindricalSurface) cylinder =
      new Geom_CylindricalSurface(frame, offset.norm());
  // (u, v) = (angle from `offset`, height along `normal` from `centre`).
  const double v0 = (pa - centre).dot(normal), v1 = (pb - centre).dot(normal);
  const gp_Pnt2d corners[4] = {gp_Pnt2d(0.0, v0), gp_Pnt2d(angle, v0 + rise),
                               gp_Pnt2d(angle, v1 + rise), gp_Pnt2d(0.0, v1)};
  BRepBuilderAPI_MakeWire wire;
  for (int k = 0; k < 4; ++k) {
    const gp_Pnt2d& p = corners[k];
    const gp_Pnt2d& q = corners[(k + 1) % 4];
    const double length = p.Distance(q);
    const Handle(Geom2d_Line) line = new Geom2d_Line(p, gp_Dir2d(q.X() - p.X(), q.Y() - p.Y()));
    TopoDS_Edge side = BRepBuilderAPI_MakeEdge(line, cylinder, 0.0, length).Edge();
    BRepLib::BuildCurves3d(side);
    wire.Add(side);
  }
  if (!wire.IsDone()) return std::nullopt;
  BRepBuilderAPI_MakeFace face(cylinder, wire.Wire(), true);
  if (!face.IsDone()) return std::nullopt;
  return face.Face();
}

}  // namespace

namespace {

// The helix's sweep in pieces of at most half a turn, each sewn from the tool's faces.
std::vector<TopoDS_Shape> helix_piece_solids(const Cutter& cutter, const Move& helix) {
  try {
    const Vec3 axis = helix.start_axis.normalized();
    const Vec3 normal = helix.normal.normalized();
    const Vec3 radial =
        helix.start - helix.center - (helix.start - helix.center).dot(normal) * normal;
    const double big_r = radial.norm();
    const double rho = cutter.profile().max_radius();
    const double reach = std::hypot(rho, cutter.profile().height());
    if (!(big_r > rho + 1e-6 * reach)) {
      throw ComputationError(fmt::format(
          "{}: the B-rep workpiece sweeps helices whose radius exceeds the tool's ({:g} mm "
          "against {:g} mm)",
          cutter.name(), big_r, rho));
    }
    // Pieces short enough that no piece's sweep comes back over itself: with the end tools
    // reaching asin(ρ/R) beyond its angles, at most half a turn.
    const double most = std::min(M_PI, 2.0 * M_PI - 2.0 * std::asin(rho / big_r) - 1e-3);
    const int pieces = static_cast<int>(std::ceil(helix.sweep / most));
    const double angle = helix.sweep / pieces, rise = helix.axial / pieces;
    // The tool axis's velocity per radian: ω × (A − C) plus the rise. Under a screw about an
    // axis parallel to the tool's, n·v(p) = n·(that velocity) on the whole tool (ω × (p − A) is
    // tangent to the tool's circles), so the silhouette is the one of a line along it.
    const Vec3 travel = normal.cross(radial);
    const Vec3 per_radian = travel + (helix.axial / helix.sweep) * normal;
    const Frame frame = Frame::from_z(helix.start, axis, Vec3::UnitX());
    const Vec3 d_local = frame.direction_to_local(angle * per_radian);
    const gp_Trsf to_world = placement(helix.start, axis);
    std::vector<TopoDS_Face> sheets;
    const std::vector<Plane> planes = silhouette_planes(cutter, d_local, sheets);
    const TopoDS_Shape local_faces =
        cut_faces(local_tool(cutter), planes, 4.0 * (reach + big_r), cutter, sheets);
    // `velocity` and `along`: the tool axis's velocity and direction of travel at the piece's
    // start (they turn with the pieces).
    const auto trails = [](const Vec3& at, const Vec3& n, const Vec3& start, const Vec3& velocity,
                           const Vec3& along) {
      const double lead = n.dot(velocity) / velocity.norm();
      return std::abs(lead) > 1e-9 ? lead < 0.0 : (at - start).dot(along) < 0.0;
    };
    const double expected = line_swept_volume(cutter, d_local);
    // The pipe shells approximate the screwed edges within 1e-7 mm; sewn within a relative
    // 1e-6 of the tool's reach, as the other sweeps.
    constexpr double kPipeTolerance = 1e-6;
    std::vector<TopoDS_Shape> solids;
    for (int k = 0; k < pieces; ++k) {
      // The piece's start: the helix's start turned by k·angle and raised by k·rise.
      const gp_Trsf advance = screw_motion(helix.center, normal, k * angle, k * rise);
      const gp_Trsf screw = screw_motion(helix.center, normal, angle, rise);
      const gp_Trsf place = advance.Multiplied(to_world);
      const TopoDS_Shape faces = BRepBuilderAPI_Transform(local_faces, place, true).Shape();
      const gp_Pnt tip = point(helix.start).Transformed(advance);
      const Vec3 start(tip.X(), tip.Y(), tip.Z());
      // The spine: the tip's helix on its cylinder, as a line in (angle, height).
      const Vec3 piece_radial = start - helix.center - (start - helix.center).dot(normal) * normal;
      const Handle(Geom_CylindricalSurface) cylinder = new Geom_CylindricalSurface(
          gp_Ax3(point(start - piece_radial), direction(normal), direction(piece_radial)), big_r);
      // (u, v) = (angle about the axis, height along it).
      const Handle(Geom2d_Line) line = new Geom2d_Line(gp_Pnt2d(0.0, 0.0), gp_Dir2d(angle, rise));
      const double length = std::hypot(angle, rise);
      TopoDS_Edge spine_edge = BRepBuilderAPI_MakeEdge(line, cylinder, 0.0, length).Edge();
      BRepLib::BuildCurves3d(spine_edge);
      const TopoDS_Wire spine = BRepBuilderAPI_MakeWire(spine_edge).Wire();
      const auto band = [&](const TopoDS_Edge& edge) -> TopoDS_Shape {
        // A ruling of the tool's cylinder (a segment along the helix's axis) screws along the
        // cylinder about that axis through it: that cylinder's face between the segment and its
        // screwed copy, exactly (a parallelogram in its (angle, height)), not a pipe shell's
        // B-spline: the bore's walls of all pieces and turns lie on one surface, and a disc's
        // circle crosses them analytically (the helix engagement test runs in 9.4 s, not 11.7).
        if (const std::optional<TopoDS_Face> wall =
                screwed_ruling(edge, helix.center, normal, angle, rise)) {
          return *wall;
        }
        BRepOffsetAPI_MakePipeShell pipe(spine);
        pipe.SetMode(direction(normal));  // a fixed binormal: the screw motion
        pipe.SetTolerance(1e-7, 1e-7, 1e-6);
        pipe.Add(BRepBuilderAPI_MakeWire(edge).Wire(), false, false);
        pipe.Build();
        check_done(pipe.IsDone(), "sweeping the silhouette along the helix", cutter);
        return pipe.Shape();
      };
      const TopoDS_Shape swept = sewn_sweep(
          faces,
          [&](const Vec3& at, const Vec3& n) {
            return trails(at, n, start, turned(advance, per_radian), turned(advance, travel));
          },
          screw, band, kPipeTolerance * reach, cutter);
      check_volume(swept, expected, cutter, "helix's swept volume");
      solids.push_back(swept);
    }
    return solids;
  } catch (const Standard_Failure& e) {
    throw ComputationError(fmt::format("{}: OpenCASCADE could not build the helix's sweep ({})",
                                       cutter.name(), e.GetMessageString()));
  }
}

}  // namespace

std::vector<TopoDS_Shape> tilt_sweep_solids(const Cutter& cutter, const Move& move) {
  const Vec3 tip = move.start, a0 = move.start_axis.normalized(), mid = move.axis(0.5);
  if (move.is_arc() || (move.end - move.start).norm() > tol::kLength) {
    throw ComputationError(fmt::format("{}: not a tilt in place (the tip moves)", cutter.name()));
  }
  // L along a0 × the middle axis (slerp turns a0 through it, antipodal axes too), the turn
  // twice the angle to the middle.
  const Vec3 turn = a0.cross(mid);
  const double angle = 2.0 * std::atan2(turn.norm(), a0.dot(mid));
  if (!(angle > tol::kAngle)) {
    throw ComputationError(fmt::format("{}: not a tilt in place (the axis stays)", cutter.name()));
  }
  // The radius never narrows towards the top: every piece's tangent keeps a ρ component ≥ 0
  // (arcs, at most half circles, checked at both ends and the middle).
  for (const ProfileSegment& piece : cutter.profile().segments()) {
    if (piece.length() < 1e-9) continue;
    for (const double u : {0.0, 0.5, 1.0}) {
      if (piece.tangent_at(u).x() < -1e-12) {
        throw ComputationError(fmt::format(
            "{}: a tilt in place is swept for tools whose radius never narrows towards the top; "
            "this profile narrows between heights {:.4g} and {:.4g} mm",
            cutter.name(), piece.min_z(), piece.max_z()));
      }
    }
  }
  try {
    // In the tool's frame with x along L: the meridian section lies in the xz plane (local_tool's
    // own), its other half turned half round the axis, and a turn about +x by `angle` takes +z to
    // the end axis (a1 = cos·a0 + sin·(L × a0), and L × a0 is the frame's −y).
    const Vec3 along = turn.normalized();
    const Profile& profile = cutter.profile();
    const double height = profile.height(), top = profile.top_radius();
    const TopoDS_Face half = meridian_section(cutter);
    gp_Trsf half_turn;
    half_turn.SetRotation(gp_Ax1(gp::Origin(), gp::DZ()), M_PI);
    const TopoDS_Shape other = BRepBuilderAPI_Transform(half, half_turn, true).Shape();
    std::vector<TopoDS_Shape> faces{half, other};
    // The top disc in halves either side of its diameter along x: a whole disc's two halves
    // lie at the same distances from the line, and its revolved rim would overlap itself.
    if (top > 1e-9) {
      for (const double side : {1.0, -1.0}) {
        const gp_Pnt left(-top, 0, height), right(top, 0, height), apex(0, side * top, height);
        const Handle(Geom_TrimmedCurve) rim = GC_MakeArcOfCircle(left, apex, right).Value();
        const TopoDS_Wire half_disc =
            BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(rim).Edge(),
                                    BRepBuilderAPI_MakeEdge(right, left).Edge())
                .Wire();
        faces.push_back(BRepBuilderAPI_MakeFace(half_disc, /*OnlyPlane=*/true).Face());
      }
    }
    const gp_Trsf to_world = placement(tip, a0, along);
    std::vector<TopoDS_Shape> solids{tool_solid(cutter, tip, a0),
                                     tool_solid(cutter, tip, move.end_axis.normalized())};
    for (const TopoDS_Shape& face : faces) {
      TopExp_Explorer solid(revolved(face, gp_Ax1(gp::Origin(), gp::DX()), angle,
                                     "revolving the section about the tilt's line", cutter),
                            TopAbs_SOLID);
      check_done(solid.More(), "revolving the section about the tilt's line", cutter);
      solids.push_back(BRepBuilderAPI_Transform(solid.Current(), to_world, true).Shape());
    }
    for (const TopoDS_Shape& solid : solids) {
      check_done(BRepCheck_Analyzer(solid).IsValid(), "checking the tilt's solids", cutter);
    }
    return solids;
  } catch (const Standard_Failure& e) {
    throw ComputationError(fmt::format("{}: OpenCASCADE could not sweep the tilt in place ({})",
                                       cutter.name(), e.GetMessageString()));
  }
}

std::vector<TopoDS_Shape> helix_sweep_solids(const Cutter& cutter, const Move& helix) {
  // Over more than a turn, the poses a whole turn apart differ by a shift of δ (the pitch)
  // along the tool's axis. For a tool whose radius never shrinks upwards (a convex profile that
  // ends in a straight side at its largest radius) and whose side is at least δ tall, the poses of
  // the turn at the low end of the helix, each with its tool lengthened to the top of the highest
  // pose over it, hold every other pose, and their union is that of the poses over them. So the
  // sweep is that turn's, with taller tools: exactly the same solid, without the turns' floors cut
  // under one another (OpenCASCADE's cuts along such B-spline floors gave invalid solids from the
  // fifth half turn on).
  const double turns = helix.sweep / (2.0 * M_PI);
  const Vec3 axis = helix.start_axis.normalized();
  const double rise = helix.axial * helix.normal.normalized().dot(axis);  // along the tool axis
  const double pitch = std::abs(rise) / turns;
  const Profile& profile = cutter.profile();
  const ProfileSegment& top = profile.segments().back();
  const double rho = profile.max_radius();
  const bool straight_side = top.kind == ProfileSegment::Kind::kLine &&
                             std::abs(top.start.x() - rho) <= 1e-12 * rho &&
                             std::abs(top.end.x() - rho) <= 1e-12 * rho;
  if (turns <= 1.0 || pitch == 0.0 || !straight_side || top.end.y() - top.start.y() < pitch) {
    return helix_piece_solids(cutter, helix);
  }
  const auto taller = [&](int turns_over) {
    std::vector<ProfileSegment> segments = profile.segments();
    segments.back() =
        ProfileSegment::line(top.start, Vec2(top.end.x(), top.end.y() + turns_over * pitch));
    CutterOptions options;
    options.name = cutter.name();
    options.flutes = cutter.flutes();
    return Cutter(Profile(std::move(segments), cutter.name()), options);
  };
  // The turn at the low end, in u: its poses with m − 1 whole turns over them, then those with
  // m (m = ⌊turns⌋; one part when the helix makes whole turns).
  const int m = static_cast<int>(std::floor(turns + 1e-9));
  const double tau = 1.0 / turns;
  struct Part {
    double u0, u1;
    int over;
  };
  std::vector<Part> parts;
  if (rise < 0.0) {  // going down: the last turn
    const double split = std::min(1.0, m / turns);
    parts.push_back({1.0 - tau, split, m - 1});
    if (split < 1.0) parts.push_back({split, 1.0, m});
  } else {  // going up: the first turn
    const double split = std::max(0.0, 1.0 - m / turns);
    if (split > 0.0) parts.push_back({0.0, split, m});
    parts.push_back({split, tau, m - 1});
  }
  std::vector<TopoDS_Shape> solids;
  for (const Part& part : parts) {
    if (part.u1 - part.u0 <= 1e-9) continue;
    std::vector<TopoDS_Shape> pieces =
        helix_piece_solids(taller(part.over), helix.part(part.u0, part.u1));
    solids.insert(solids.end(), pieces.begin(), pieces.end());
  }
  return solids;
}

namespace {

// The height above the tip of the axis point whose velocity orients a lofted pose (and cuts
// its faces where the grazing curve is refused, as a line's silhouette): the centre of the
// profile's lowest arc (a ball's, a bull-nose corner's), where such a tool cuts, else the tip.
double reference_height(const Profile& profile) {
  for (const ProfileSegment& s : profile.segments()) {
    if (s.kind == ProfileSegment::Kind::kArc && (s.end - s.start).norm() >= 1e-9) {
      return s.center.y();
    }
  }
  return 0.0;
}

// The rigid motion of the tool at an instant, in its frame (tip at the origin): the tip's
// velocity and the angular velocity. A surface point p with outward normal n moves into the
// material where f = n·(v + ω × p) > 0 (Aras 2008 eq. 5.18).
struct Twist {
  Vec3 v, omega;
  double f(const Vec3& p, const Vec3& n) const { return n.dot(v + omega.cross(p)); }
};

// Cuts that hold the tool's grazing curve (f = 0) under `twist` exactly, for lofting: a sphere's
// great circle square to its centre's velocity (a plane); on a disc (a flat bottom, the top)
// the line where f, linear across it, vanishes (the plane through it along the axis); on a
// cylinder, cone or torus, for each profile point (ρ, z) with normal (n_ρ, n_z) at azimuth θ,
//   f(θ) = (n_ρ v_x − k ω_y) cos θ + (n_ρ v_y + k ω_x) sin θ + n_z v_z,   k = ρ n_z − z n_ρ,
// whose two roots, followed along the piece, are two curves; each is cut by a sheet ruled by
// segments along the profile's normal through it (square to the surface, so that none lies in
// a disc's plane), its guide curves interpolating 17 points (33 on an arc; twice that less one
// through a fold) spaced evenly along the curve's length. Where the roots stop part-way at one end
// of a piece (a fold: a torus whose curve turns on it, as under a ramp), one sheet runs out along
// one root and back along the other. Returns false where the roots are on two stretches of a piece,
// or a piece other than a ball reaches the axis (a pointed cone): the line's silhouette is then
// used.
bool grazing_cuts(const Cutter& cutter, const Twist& twist, std::vector<Plane>& planes,
                  std::vector<TopoDS_Face>& sheets) {
  const Profile& profile = cutter.profile();
  const double speed = twist.v.norm() + twist.omega.norm() * profile.height();
  // How far the sheets reach into the tool and out of it along the normal: the same for every
  // piece, so that two pieces' sheets meet along one segment at their joint.
  double inward = profile.max_radius(), outward = 1.0 + 0.5 * profile.max_radius();
  for (const ProfileSegment& s : profile.segments()) {
    if ((s.end - s.start).norm() < 1e-9 || s.is_horizontal()) continue;
    if (s.kind == ProfileSegment::Kind::kArc && std::abs(s.center.x()) < 1e-9) continue;
    const double rho = std::min(s.start.x(), s.end.x());
    if (!(rho > 1e-9)) return false;
    inward = std::min(inward, 0.25 * rho);
    if (s.kind == ProfileSegment::Kind::kArc) inward = std::min(inward, 0.25 * s.radius);
  }
  for (const ProfileSegment& s : profile.segments()) {
    if ((s.end - s.start).norm() < 1e-9) continue;
    if (s.kind == ProfileSegment::Kind::kArc && std::abs(s.center.x()) < 1e-9) {
      const Vec3 centre(0.0, 0.0, s.center.y());
      const Vec3 v = twist.v + twist.omega.cross(centre);
      if (v.norm() > 1e-12 * speed) planes.push_back({centre, v.normalized()});
      continue;
    }
    if (s.kind == ProfileSegment::Kind::kLine && s.is_horizontal()) {
      // f = n_z (v_z + ω_x y − ω_y x) on the disc at height z.
      const Vec3 g(-twist.omega.y(), twist.omega.x(), 0.0);
      const double reach = std::max(s.start.x(), s.end.x());
      if (g.norm() > 1e-12 * speed && std::abs(twist.v.z()) < g.norm() * reach) {
        const double z = s.start.y();
        const Vec3 origin = -twist.v.z() * g / g.squaredNorm() + Vec3(0.0, 0.0, z);
        planes.push_back({origin, g.normalized()});
      }
      continue;
    }
    // A corner's grazing curve can turn by a quarter turn round the axis over its arc.
    const int kPoints = s.kind == ProfileSegment::Kind::kArc ? 33 : 17;
    // f(θ)'s roots at the profile point s(u), if it has any.
    struct Roots {
      Vec2 point, normal;
      double beta = 0.0, half = 0.0;  // the roots are β ± half
    };
    const auto roots_at = [&](double u, Roots& r) {
      r.point = s.point_at(u);
      r.normal = s.normal_at(u);
      const double rho = r.point.x(), z = r.point.y();
      const double kk = rho * r.normal.y() - z * r.normal.x();
      const double a = r.normal.x() * twist.v.x() - kk * twist.omega.y();
      const double b = r.normal.x() * twist.v.y() + kk * twist.omega.x();
      const double c = r.normal.y() * twist.v.z();
      const double amplitude = std::hypot(a, b);
      if (!(amplitude > 1e-12 * speed) || std::abs(c) > amplitude) return false;
      r.beta = std::atan2(b, a);
      r.half = std::acos(-c / amplitude);
      return true;
    };
    std::vector<bool> has(kPoints);
    int with_roots = 0;
    Roots r;
    for (int k = 0; k < kPoints; ++k) {
      has[k] = roots_at(static_cast<double>(k) / (kPoints - 1), r);
      with_roots += has[k] ? 1 : 0;
    }
    if (with_roots == 0) continue;  // wholly leading or trailing
    // The parameter τ ∈ [0, 1] the curves are followed along: the profile's own over the whole
    // piece, or, where the roots stop part-way at one of its ends, from the other end (the
    // joint) to the fold where the two roots meet (found by bisection), quadratic in τ: near a
    // fold the roots part as the square root of the distance from it.
    bool fold = false;
    double with = 1.0, joint = 0.0;
    if (with_roots != kPoints) {
      // One run of points with roots, reaching one end of the piece: else refused.
      const bool at_end = has[kPoints - 1];
      if (has[0] == at_end) return false;
      int changes = 0;
      for (int k = 1; k < kPoints; ++k) changes += has[k] != has[k - 1] ? 1 : 0;
      if (changes != 1) return false;
      double without = 0.0;  // in u, bracketing the fold with `with`
      for (int k = 1; k < kPoints; ++k) {
        if (has[k] != has[k - 1]) {
          without = static_cast<double>(at_end ? k - 1 : k) / (kPoints - 1);
          with = static_cast<double>(at_end ? k : k - 1) / (kPoints - 1);
        }
      }
      for (int step = 0; step < 50; ++step) {
        const double mid = 0.5 * (without + with);
        (roots_at(mid, r) ? with : without) = mid;
      }
      joint = at_end ? 1.0 : 0.0;
      fold = true;
    }
    const auto u_of = [&](double tau) {
      return fold ? with + (joint - with) * (1.0 - tau) * (1.0 - tau) : tau;
    };
    const auto turn_near = [](double x, double to) {
      return x + 2.0 * M_PI * std::round((to - x) / (2.0 * M_PI));
    };
    // Both roots, followed from point to point (each within a turn of the one before) over a
    // dense table in τ.
    const int dense = 16 * (kPoints - 1) + 1;
    std::vector<double> taus(dense);
    std::array<std::vector<double>, 2> roots{std::vector<double>(dense),
                                             std::vector<double>(dense)};
    std::vector<Vec2> profile_points(dense);
    for (int j = 0; j < dense; ++j) {
      taus[j] = static_cast<double>(j) / (dense - 1);
      if (!roots_at(u_of(taus[j]), r)) return false;
      profile_points[j] = r.point;
      double r1 = r.beta + r.half, r2 = r.beta - r.half;
      if (j > 0) {
        r1 = turn_near(r1, roots[0][j - 1]);
        r2 = turn_near(r2, roots[0][j - 1]);
        if (std::abs(r2 - roots[0][j - 1]) < std::abs(r1 - roots[0][j - 1])) std::swap(r1, r2);
        r2 = turn_near(r2, roots[1][j - 1]);
      }
      roots[0][j] = r1;
      roots[1][j] = r2;
    }
    // Each root's curve through kPoints points spaced evenly along its length on the tool
    // (points evenly spaced in τ would leave a curve that swings fast round the axis, as it does
    // near a fold, too few), each point exact: the root at its τ nearest the table's.
    struct Curve {
      std::vector<Vec2> points, normals;
      std::vector<double> theta;
    };
    const auto on_tool = [](const Vec2& q, double theta) {
      return Vec3(q.x() * std::cos(theta), q.x() * std::sin(theta), q.y());
    };
    std::array<Curve, 2> branches;
    for (int b = 0; b < 2; ++b) {
      std::vector<double> length(dense, 0.0);
      for (int j = 1; j < dense; ++j) {
        length[j] = length[j - 1] + (on_tool(profile_points[j], roots[b][j]) -
                                     on_tool(profile_points[j - 1], roots[b][j - 1]))
                                        .norm();
      }
      if (!(length.back() > 0.0)) return false;
      int j = 0;
      for (int k = 0; k < kPoints; ++k) {
        const double target = length.back() * k / (kPoints - 1);
        while (j + 2 < dense && length[j + 1] < target) ++j;
        const double span = length[j + 1] - length[j];
        const double f = span > 0.0 ? std::clamp((target - length[j]) / span, 0.0, 1.0) : 0.0;
        const double tau = k + 1 < kPoints ? taus[j] + f * (taus[j + 1] - taus[j]) : 1.0;
        const double guess = roots[b][j] + f * (roots[b][j + 1] - roots[b][j]);
        if (!roots_at(u_of(tau), r)) return false;
        const double r1 = turn_near(r.beta + r.half, guess), r2 = turn_near(r.beta - r.half, guess);
        branches[b].points.push_back(r.point);
        branches[b].normals.push_back(r.normal);
        branches[b].theta.push_back(std::abs(r1 - guess) <= std::abs(r2 - guess) ? r1 : r2);
      }
    }
    // The two roots' curves, or, with a fold, one curve out along the first and back along the
    // second, through the fold's point on both: their middle.
    std::vector<Curve> curves;
    if (!fold) {
      curves.assign(branches.begin(), branches.end());
    } else {
      Curve c = branches[0];
      const double other = turn_near(branches[1].theta.back(), c.theta.back());
      c.theta.back() = 0.5 * (c.theta.back() + other);
      for (int k = kPoints - 2; k >= 0; --k) {
        c.points.push_back(branches[1].points[k]);
        c.normals.push_back(branches[1].normals[k]);
        c.theta.push_back(turn_near(branches[1].theta[k], c.theta.back()));
      }
      curves.push_back(std::move(c));
    }
    for (const Curve& curve : curves) {
      const int n = static_cast<int>(curve.theta.size());
      Handle(TColgp_HArray1OfPnt) near = new TColgp_HArray1OfPnt(1, n);
      Handle(TColgp_HArray1OfPnt) far = new TColgp_HArray1OfPnt(1, n);
      Handle(TColStd_HArray1OfReal) params = new TColStd_HArray1OfReal(1, n);
      const auto at = [&](int k, double t) {
        const Vec2 q = curve.points[k] + t * curve.normals[k];
        const double theta = curve.theta[k];
        return gp_Pnt(q.x() * std::cos(theta), q.x() * std::sin(theta), q.y());
      };
      // Parameters by the chord length along the curve on the tool.
      double length = 0.0;
      for (int k = 0; k < n; ++k) {
        if (k > 0) length += at(k, 0.0).Distance(at(k - 1, 0.0));
        params->SetValue(k + 1, length);
        near->SetValue(k + 1, at(k, -inward));
        far->SetValue(k + 1, at(k, outward));
      }
      if (!(length > 0.0)) return false;
      for (int k = 0; k < n; ++k) params->SetValue(k + 1, params->Value(k + 1) / length);
      GeomAPI_Interpolate near_curve(near, params, false, 1e-12),
          far_curve(far, params, false, 1e-12);
      near_curve.Perform();
      far_curve.Perform();
      check_done(near_curve.IsDone() && far_curve.IsDone(), "a grazing curve", cutter);
      sheets.push_back(
          BRepBuilderAPI_MakeFace(GeomFill::Surface(near_curve.Curve(), far_curve.Curve()), 1e-9)
              .Face());
    }
  }
  return true;
}

// One pose of a lofted move, in the world: the tool's faces that trail and those that lead,
// and the silhouette between them as one closed wire.
struct LoftPose {
  std::vector<TopoDS_Face> trailing, leading;
  TopoDS_Wire silhouette;
  std::vector<int> kinds;  // each edge's curve type (GeomAbs_CurveType), in the chain's order
};

// The pose at u: the tool cut along its grazing curve (grazing_cuts; where those are refused, the
// silhouette of a line along the velocity of its axis point at `reference` above the tip), in
// the tool's frame with x along that velocity's part square to the axis, so that the faces' seam
// lies on the leading side, off the curve. The curve's edges are chained from the first round
// the tool's shadow along that velocity (by the angle of their midpoints about the shadow of the
// axis's middle, anticlockwise) along their shared vertices: the same chain at every pose while
// the curve keeps its kind of edges.
LoftPose loft_pose(const Cutter& cutter, const TopoDS_Solid& tool, const Move& move, double u,
                   double reference, double big) {
  const Vec3 tip = move.position(u), axis = move.axis(u);
  const Vec3 velocity = move.tangent(u) + move.axis_rate(u).cross(reference * axis);
  if (!(velocity.norm() > 0.0)) {
    throw ComputationError(fmt::format("{}: the tool does not move", cutter.name()));
  }
  const Vec3 square = velocity - velocity.dot(axis) * axis;
  const Vec3 hint = square.norm() > 1e-12 * velocity.norm() ? square : Vec3::UnitX();
  const Frame frame = Frame::from_z(tip, axis, hint);
  const Vec3 d = frame.direction_to_local(velocity);
  const Twist twist{frame.direction_to_local(move.tangent(u)),
                    frame.direction_to_local(move.axis_rate(u))};
  std::vector<TopoDS_Face> sheets;
  std::vector<Plane> planes;
  if (!grazing_cuts(cutter, twist, planes, sheets)) {
    sheets.clear();
    planes = silhouette_planes(cutter, d, sheets);
  }
  const TopoDS_Shape local = cut_faces(tool, planes, big, cutter, sheets);
  BRepBuilderAPI_Transform place(local, placement(tip, axis, hint), /*Copy=*/true);
  check_done(place.IsDone(), "placing the tool", cutter);
  // A face trails where the motion draws it out of the material (f < 0); one the motion runs
  // along (f = 0 all over: a disc under a level line) as a line's.
  const double speed = twist.v.norm() + twist.omega.norm() * cutter.profile().height();
  const auto trails = [&](const Vec3& at, const Vec3& normal) {
    const double f = twist.f(at, normal);
    return std::abs(f) > 1e-9 * speed ? f < 0.0 : Trailing{d}(at, normal);
  };
  const Sides sorted = sides(local, trails, cutter);
  LoftPose pose;
  for (const TopoDS_Face& face : sorted.trailing) {
    pose.trailing.push_back(TopoDS::Face(place.ModifiedShape(face)));
  }
  for (const TopoDS_Face& face : sorted.leading) {
    pose.leading.push_back(TopoDS::Face(place.ModifiedShape(face)));
  }
  // The silhouette's edges, each with its angle round the shadow and its direction.
  const Vec3 e1 = Vec3::UnitY(), e2 = d.cross(e1).normalized();
  const Vec3 centre(0.0, 0.0, 0.5 * cutter.profile().height());
  const auto angle = [&](const gp_Pnt& p) {
    const Vec3 q = Vec3(p.X(), p.Y(), p.Z()) - centre;
    return std::atan2(q.dot(e2), q.dot(e1));
  };
  const auto turn = [](double a) { return std::remainder(a, 2.0 * M_PI); };
  struct Link {
    double angle;
    TopoDS_Edge edge;
    int kind;
  };
  std::vector<Link> links;
  for (TopoDS_Edge edge : sorted.silhouette) {
    const BRepAdaptor_Curve curve(edge);
    const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
    const double a0 = angle(curve.Value(t0)), am = angle(curve.Value(0.5 * (t0 + t1))),
                 a1 = angle(curve.Value(t1));
    const bool forward = turn(am - a0) + turn(a1 - am) > 0.0;
    if (forward == (edge.Orientation() == TopAbs_REVERSED)) edge.Reverse();
    links.push_back({am, edge, curve.GetType()});
  }
  const auto not_closed = [&] {
    return ComputationError(
        fmt::format("{}: the silhouette of a pose is not one closed curve", cutter.name()));
  };
  if (links.empty()) throw not_closed();
  // From the edge first round the shadow, along the edges' shared vertices.
  std::sort(links.begin(), links.end(),
            [](const Link& a, const Link& b) { return a.angle < b.angle; });
  std::vector<bool> used(links.size(), false);
  used[0] = true;
  std::vector<const Link*> chain{&links[0]};
  const TopoDS_Vertex start = TopExp::FirstVertex(links[0].edge, true);
  TopoDS_Vertex end = TopExp::LastVertex(links[0].edge, true);
  while (!end.IsSame(start)) {
    std::size_t next = links.size();
    for (std::size_t k = 0; k < links.size() && next == links.size(); ++k) {
      if (used[k]) continue;
      if (TopExp::LastVertex(links[k].edge, true).IsSame(end)) links[k].edge.Reverse();
      if (TopExp::FirstVertex(links[k].edge, true).IsSame(end)) next = k;
    }
    if (next == links.size()) throw not_closed();
    used[next] = true;
    chain.push_back(&links[next]);
    end = TopExp::LastVertex(links[next].edge, true);
  }
  if (chain.size() != links.size()) throw not_closed();
  BRepBuilderAPI_MakeWire wire;
  for (const Link* link : chain) {
    // The placed copy, in the direction chosen here.
    wire.Add(TopoDS::Edge(place.ModifiedShape(link->edge).Oriented(link->edge.Orientation())));
    pose.kinds.push_back(link->kind);
  }
  if (!wire.IsDone() || !wire.Wire().Closed()) throw not_closed();
  pose.silhouette = wire.Wire();
  return pose;
}

// The largest distance from points of the swept solid's faces inside `within` (the band's and
// the end tools' faces kept: a face kept whole where the grazing curve crosses it would hold
// points inside the sweep) to the boundary of the true sweep: on a 12 × 12 grid over each
// face's parameters, the points on the face, each at the distance to the nearest pose (the
// signed distance to the tool, minimised over u by a scan of 256 poses refined by golden
// section).
double loft_deviation(const std::vector<TopoDS_Face>& faces, const Cutter& cutter, const Move& move,
                      const Aabb& within) {
  const Profile& profile = cutter.profile();
  const auto distance = [&](const Vec3& p, double u) {
    const Vec3 q = p - move.position(u), a = move.axis(u);
    const double z = q.dot(a);
    return profile.signed_distance((q - z * a).norm(), z);
  };
  constexpr int kGrid = 12, kScan = 256;
  double worst = 0.0;
  for (const TopoDS_Face& face : faces) {
    double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    const BRepAdaptor_Surface surface(face);
    for (int i = 0; i < kGrid; ++i) {
      for (int j = 0; j < kGrid; ++j) {
        const gp_Pnt2d uv(u0 + (i + 0.5) / kGrid * (u1 - u0), v0 + (j + 0.5) / kGrid * (v1 - v0));
        const gp_Pnt g = surface.Value(uv.X(), uv.Y());
        const Vec3 p(g.X(), g.Y(), g.Z());
        if (!within.contains(p)) continue;
        if (BRepClass_FaceClassifier(face, uv, 1e-9).State() != TopAbs_IN) continue;
        int best = 0;
        double nearest = distance(p, 0.0);
        for (int k = 1; k <= kScan; ++k) {
          const double dk = distance(p, static_cast<double>(k) / kScan);
          if (dk < nearest) nearest = dk, best = k;
        }
        double lo = std::max(0, best - 1) / static_cast<double>(kScan);
        double hi = std::min(kScan, best + 1) / static_cast<double>(kScan);
        const double r = 0.5 * (std::sqrt(5.0) - 1.0);
        double a = hi - r * (hi - lo), b = lo + r * (hi - lo);
        double da = distance(p, a), db = distance(p, b);
        for (int k = 0; k < 40; ++k) {
          if (da < db) {
            hi = b, b = a, db = da, a = hi - r * (hi - lo), da = distance(p, a);
          } else {
            lo = a, a = b, da = db, b = lo + r * (hi - lo), db = distance(p, b);
          }
        }
        nearest = std::min({nearest, da, db});
        worst = std::max(worst, std::abs(nearest));
      }
    }
  }
  return worst;
}

}  // namespace

namespace {

// The tool's solid and the sizes every pose of a loft uses.
struct LoftTool {
  TopoDS_Solid tool;
  double reach = 0.0, big = 0.0, reference = 0.0;
  explicit LoftTool(const Cutter& cutter)
      : tool(local_tool(cutter)),
        reach(std::hypot(cutter.profile().max_radius(), cutter.profile().height())),
        big(4.0 * reach),
        reference(reference_height(cutter.profile())) {}
};

// lofted_sweep_solid, or nothing where the grazing curve changes its kind of edges along the
// move (`kinds` then says from what to what).
std::optional<LoftedSweep> loft_one(const Cutter& cutter, const LoftTool& t, const Move& move,
                                    double tolerance, const Aabb& within,
                                    std::array<std::size_t, 2>& kinds) {
  double deviation = std::numeric_limits<double>::infinity();
  int sections = 4;
  for (; sections <= 16; sections *= 2) {
    std::vector<LoftPose> poses;
    for (int i = 0; i <= sections; ++i) {
      poses.push_back(
          loft_pose(cutter, t.tool, move, static_cast<double>(i) / sections, t.reference, t.big));
      if (poses.back().kinds != poses.front().kinds) {
        kinds = {poses.front().kinds.size(), poses.back().kinds.size()};
        return std::nullopt;
      }
    }
    BRepOffsetAPI_ThruSections loft(/*isSolid=*/false, /*ruled=*/false, 1e-7);
    loft.CheckCompatibility(false);
    for (const LoftPose& pose : poses) loft.AddWire(pose.silhouette);
    loft.Build();
    check_done(loft.IsDone(), "lofting the silhouettes", cutter);
    BRepBuilderAPI_Sewing sewing(1e-6 * t.reach);
    std::vector<TopoDS_Face> faces = poses.front().trailing;
    faces.insert(faces.end(), poses.back().leading.begin(), poses.back().leading.end());
    for (TopExp_Explorer e(loft.Shape(), TopAbs_FACE); e.More(); e.Next()) {
      faces.push_back(TopoDS::Face(e.Current()));
    }
    for (const TopoDS_Face& face : faces) sewing.Add(face);
    const TopoDS_Solid solid = sewn_solid(sewing, cutter);
    const double previous = deviation;
    deviation = loft_deviation(faces, cutter, move, within);
    if (deviation <= tolerance) return LoftedSweep{{solid}, sections, deviation};
    // Not halved by twice the poses: the silhouettes themselves are off (a flat end's bottom
    // that a sideways tilt lifts on one side and lowers on the other), not the loft between.
    if (deviation > 0.5 * previous) break;
  }
  throw ComputationError(fmt::format(
      "{}: the loft through {} poses is {:.3g} mm off the sweep, beyond the tolerance {:g} mm",
      cutter.name(), std::min(sections, 16) + 1, deviation, tolerance));
}

ComputationError occt_failure(const Cutter& cutter, const Standard_Failure& e) {
  return ComputationError(fmt::format("{}: OpenCASCADE could not loft the move's sweep ({})",
                                      cutter.name(), e.GetMessageString()));
}

}  // namespace

LoftedSweep lofted_sweep_solid(const Cutter& cutter, const Move& move, double tolerance,
                               const Aabb& within) {
  try {
    std::array<std::size_t, 2> kinds{};
    std::optional<LoftedSweep> loft =
        loft_one(cutter, LoftTool(cutter), move, tolerance, within, kinds);
    if (!loft) {
      throw ComputationError(fmt::format(
          "{}: the silhouette changes its kind of edges along the move ({} edges, then {})",
          cutter.name(), kinds[0], kinds[1]));
    }
    return *loft;
  } catch (const Standard_Failure& e) {
    throw occt_failure(cutter, e);
  }
}

LoftedSweep lofted_sweep_parts(const Cutter& cutter, const Move& move, double tolerance,
                               const Aabb& within) {
  if (!(tolerance > 0.0)) {
    throw ComputationError(fmt::format("{}: loft tolerance {} mm, expected a positive length",
                                       cutter.name(), tolerance));
  }
  try {
    const LoftTool t(cutter);
    std::array<std::size_t, 2> kinds{};
    // The whole move first; a pose of it right at a change (see below) fails it as well.
    std::optional<ComputationError> whole_failed;
    try {
      if (std::optional<LoftedSweep> whole = loft_one(cutter, t, move, tolerance, within, kinds)) {
        return *whole;
      }
    } catch (const ComputationError& e) {
      whole_failed = e;
    }
    // How far a point of the tool moves per unit of the move's parameter, at most.
    const double speed = move.length() + move.axis_angle() * t.reach;
    // Brackets are bisected down to `width` from each side, so are at most `2 × width` wide.
    const double width = 0.5 * tolerance / speed;
    // Right at a change the cuts may leave a sliver face that no pose can sort, or curves that
    // OpenCASCADE cannot interpolate: such a pose counts as neither kind (no kinds).
    const auto kinds_near_change = [&](double u) {
      try {
        return loft_pose(cutter, t.tool, move, u, t.reference, t.big).kinds;
      } catch (const ComputationError&) {
      } catch (const Standard_Failure&) {
      }
      return std::vector<int>{};
    };
    // The changes: between 17 poses (one of them right at a change moved along by a bracket),
    // each bisected down to `width` from both sides (the last pose of the kind before, the first
    // of the kind after).
    constexpr int kSamples = 16, kMostHalvings = 60, kMostBracketTools = 16;
    std::vector<double> at(kSamples + 1);
    std::vector<std::vector<int>> sampled(kSamples + 1);
    for (int i = 0; i <= kSamples; ++i) {
      at[i] = static_cast<double>(i) / kSamples;
      sampled[i] = kinds_near_change(at[i]);
      for (const double nudge : {2.0 * width, -2.0 * width}) {
        if (!sampled[i].empty() || i == 0 || i == kSamples) break;
        at[i] = static_cast<double>(i) / kSamples + nudge;
        sampled[i] = kinds_near_change(at[i]);
      }
      if (sampled[i].empty()) {
        if (whole_failed) throw *whole_failed;
        throw ComputationError(
            fmt::format("{}: the silhouette of the pose at {:.3g} of the move cannot be sorted",
                        cutter.name(), at[i]));
      }
    }
    std::vector<std::array<double, 2>> changes;
    for (int i = 1; i <= kSamples; ++i) {
      const std::vector<int>& before = sampled[i - 1];
      const std::vector<int>& after = sampled[i];
      if (after == before) continue;
      double lo = at[i - 1], hi = at[i];
      for (int step = 0; step < kMostHalvings && hi - lo > width; ++step) {
        const double mid = 0.5 * (lo + hi);
        (kinds_near_change(mid) == before ? lo : hi) = mid;
      }
      double first = lo;
      hi = at[i];
      for (int step = 0; step < kMostHalvings && hi - first > width; ++step) {
        const double mid = 0.5 * (first + hi);
        (kinds_near_change(mid) == after ? hi : first) = mid;
      }
      // A part shorter than a bracket between two changes: one bracket over both.
      if (!changes.empty() && lo - changes.back()[1] < 2.0 * width) {
        changes.back()[1] = hi;
      } else {
        changes.push_back({lo, hi});
      }
    }
    if (changes.empty()) {
      if (whole_failed) throw *whole_failed;
      throw ComputationError(fmt::format(
          "{}: the silhouette changes its kind of edges between poses that agree", cutter.name()));
    }
    LoftedSweep parts;
    parts.sections = 0;
    double u = 0.0;
    for (std::size_t k = 0; k <= changes.size(); ++k) {
      const double end = k < changes.size() ? changes[k][0] : 1.0;
      std::optional<LoftedSweep> part =
          loft_one(cutter, t, move.part(u, end), tolerance, within, kinds);
      if (!part) {
        throw ComputationError(fmt::format(
            "{}: the silhouette changes its kind of edges more than once between two of 17 "
            "poses along the move ({} edges, then {})",
            cutter.name(), kinds[0], kinds[1]));
      }
      parts.solids.push_back(part->solids.front());
      parts.sections += part->sections;
      parts.deviation = std::max(parts.deviation, part->deviation);
      if (k == changes.size()) break;
      // Across the change, the tool at the middle of each of n stretches no wider than
      // 2 width: no point of the tool moves farther than speed × 2 width = tolerance across
      // one, so none of the sweep across it is farther than half that from its pose.
      const double lo = changes[k][0], hi = changes[k][1];
      const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / (2.0 * width))));
      if (n > kMostBracketTools) {  // poses no test can sort over a long stretch
        throw ComputationError(
            fmt::format("{}: the silhouette's kind of edges cannot be told over {:.3g} of the move",
                        cutter.name(), hi - lo));
      }
      for (int j = 0; j < n; ++j) {
        const double mid = lo + (j + 0.5) * (hi - lo) / n;
        parts.solids.push_back(tool_solid(cutter, move.position(mid), move.axis(mid)));
      }
      parts.deviation = std::max(parts.deviation, 0.5 * speed * (hi - lo) / n);
      u = hi;
    }
    parts.changes = static_cast<int>(changes.size());
    return parts;
  } catch (const Standard_Failure& e) {
    throw occt_failure(cutter, e);
  }
}

}  // namespace cwe
