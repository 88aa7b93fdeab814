#include "cwe/workpiece/brep/brep_stock.hpp"

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepClass3d_SolidExplorer.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Vec.hxx>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/workpiece/brep/brep_shapes.hpp"

namespace cwe {
namespace {

Bnd_Box box_of(const TopoDS_Shape& shape) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, /*useTriangulation=*/false);
  return box;
}

int count_faces(const TopoDS_Shape& shape) {
  int n = 0;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) ++n;
  return n;
}

Aabb aabb_of(const Bnd_Box& box) {
  if (box.IsVoid()) return Aabb();
  double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
  box.Get(x0, y0, z0, x1, y1, z1);
  return Aabb{{x0, y0, z0}, {x1, y1, z1}};
}

// While alive, floating-point exceptions do not trap, and on leaving, the environment (traps and
// flags) is as before. OpenCASCADE's algorithms may divide by zero where the IEEE result is what
// they want (its face merging did, building a B-spline surface's cache on the bundled example's
// helix); the tests trap division by zero in cwe's own code.
class OcctFloatingPoint {
 public:
  OcctFloatingPoint() { feholdexcept(&saved_); }
  ~OcctFloatingPoint() { fesetenv(&saved_); }
  OcctFloatingPoint(const OcctFloatingPoint&) = delete;
  OcctFloatingPoint& operator=(const OcctFloatingPoint&) = delete;

 private:
  std::fenv_t saved_;
};

// Whether some point well inside `tool` lies inside `stock`, the stock after the tool's cut: of a
// grid of 6 × 6 × 6 over the tool's box, a point that OpenCASCADE's classifiers put inside both
// (a hit within `depth` along their rays counting as on the boundary) and that lies farther than
// `depth` from the tool's faces. OpenCASCADE has given a cut and a common that both took nothing
// where the tool crossed the stock (a bull nose's plunge and straight side at a second level
// round a block); the volume checks pass such a cut, this does not.
bool tool_left_material(const TopoDS_Shape& stock, const TopoDS_Shape& tool, double depth) {
  double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
  box_of(tool).Get(x0, y0, z0, x1, y1, z1);
  const Bnd_Box stock_box = box_of(stock);
  constexpr int kGrid = 6;
  BRepClass3d_SolidClassifier in_tool(tool);
  std::optional<BRepClass3d_SolidClassifier> in_stock;
  std::optional<BRepExtrema_DistShapeShape> to_faces;
  TopoDS_Compound faces;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      for (int k = 0; k < kGrid; ++k) {
        const gp_Pnt p(x0 + (x1 - x0) * (i + 0.5) / kGrid, y0 + (y1 - y0) * (j + 0.5) / kGrid,
                       z0 + (z1 - z0) * (k + 0.5) / kGrid);
        if (stock_box.IsOut(p)) continue;
        in_tool.Perform(p, depth);
        if (in_tool.State() != TopAbs_IN) continue;
        if (!in_stock) in_stock.emplace(stock);
        in_stock->Perform(p, depth);
        if (in_stock->State() != TopAbs_IN) continue;
        // Its distance from the tool's faces (from the solid, a point inside it is at 0).
        if (!to_faces) {
          BRep_Builder builder;
          builder.MakeCompound(faces);
          for (TopExp_Explorer f(tool, TopAbs_FACE); f.More(); f.Next()) {
            builder.Add(faces, f.Current());
          }
          to_faces.emplace();
          to_faces->LoadS2(faces);
        }
        to_faces->LoadS1(BRepBuilderAPI_MakeVertex(p).Vertex());
        if (to_faces->Perform() && to_faces->Value() > depth) return true;
      }
    }
  }
  return false;
}

// Whether a solid of `result`, where it has several, lies inside `tool`: a point just inside one
// of its faces (inside the solid by OpenCASCADE's classifier, 1e-3 to 1e-5 mm from the face)
// that the classifier puts inside the tool. A cut leaves nothing inside the swept volume, but
// OpenCASCADE's cut of a tight corner's ring left the sliver it should have taken as a solid of
// its own (0.0063 mm³ at each corner of a 6 mm bull nose's loop at radius 2.5), the stock's
// volume unchanged; the grid of tool_left_material is far too coarse to meet it.
bool solid_inside_tool(const TopoDS_Shape& result, const TopoDS_Shape& tool) {
  std::vector<TopoDS_Shape> parts;
  for (TopExp_Explorer e(result, TopAbs_SOLID); e.More(); e.Next()) parts.push_back(e.Current());
  if (parts.size() < 2) return false;
  const Bnd_Box tool_box = box_of(tool);
  for (const TopoDS_Shape& part : parts) {
    if (tool_box.IsOut(box_of(part))) continue;
    for (TopExp_Explorer f(part, TopAbs_FACE); f.More(); f.Next()) {
      const TopoDS_Face& face = TopoDS::Face(f.Current());
      gp_Pnt on;
      double u = 0, v = 0, param = 0;
      gp_Vec du, dv;
      if (!BRepClass3d_SolidExplorer::FindAPointInTheFace(face, on, u, v, param, du, dv)) continue;
      gp_Vec outward = du.Crossed(dv);
      if (outward.Magnitude() < 1e-12) continue;
      outward.Normalize();
      if (face.Orientation() == TopAbs_REVERSED) outward.Reverse();
      bool placed = false;
      for (const double step : {1e-3, 1e-4, 1e-5}) {
        const gp_Pnt inside = on.Translated(-step * outward);
        BRepClass3d_SolidClassifier in_part(part, inside, 1e-2 * step);
        if (in_part.State() != TopAbs_IN) continue;
        placed = true;
        BRepClass3d_SolidClassifier in_tool(tool, inside, 1e-2 * step);
        if (in_tool.State() == TopAbs_IN) return true;
        break;
      }
      if (placed) break;  // one point per solid
    }
  }
  return false;
}

// The largest tolerance of a shape's vertices and edges, mm: how far OpenCASCADE lets them lie
// off their faces.
double max_tolerance(const TopoDS_Shape& shape) {
  return std::max(BRep_Tool::MaxTolerance(shape, TopAbs_VERTEX),
                  BRep_Tool::MaxTolerance(shape, TopAbs_EDGE));
}

// Appends the solids of a boolean's result to `out` and returns their volume.
double solids_of(const TopoDS_Shape& shape, std::vector<BrepStock::Solid>& out) {
  double volume = 0.0;
  for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) {
    out.push_back({e.Current()});
    volume += shape_volume(e.Current());
  }
  return volume;
}

std::vector<BrepStock::Solid> solids(const std::vector<TopoDS_Shape>& shapes) {
  std::vector<BrepStock::Solid> out;
  for (const TopoDS_Shape& shape : shapes) out.push_back({shape});
  return out;
}

}  // namespace

BrepStock::BrepStock(std::unique_ptr<Solid> solid)
    : solid_(solid.release(), [](Solid* s) { delete s; }),
      volume_(shape_volume(solid_->shape)),
      faces_(count_faces(solid_->shape)) {}

BrepStock BrepStock::from_box(const Aabb& box) {
  if (box.is_empty() || !box.min.allFinite() || !box.max.allFinite() ||
      !((box.max - box.min).minCoeff() > 0.0)) {
    throw InputError("B-rep stock: the box must have a positive size along x, y and z");
  }
  auto solid = std::make_unique<Solid>();
  solid->shape = BRepPrimAPI_MakeBox(gp_Pnt(box.min.x(), box.min.y(), box.min.z()),
                                     gp_Pnt(box.max.x(), box.max.y(), box.max.z()))
                     .Shape();
  return BrepStock(std::move(solid));
}

BrepStock brep_stock(const TopoDS_Shape& shape) {
  auto solid = std::make_unique<BrepStock::Solid>();
  solid->shape = shape;
  return BrepStock(std::move(solid));
}

Aabb BrepStock::bounds() const { return aabb_of(box_of(solid_->shape)); }

Aabb BrepStock::tight_bounds() const {
  Bnd_Box tight;
  BRepBndLib::AddOptimal(solid_->shape, tight, /*useTriangulation=*/false);
  return aabb_of(tight);
}

double BrepStock::cut_all(const std::vector<Solid>& parts, std::vector<Solid>* removed,
                          bool merge_faces) {
  // All or nothing: a part that fails leaves the stock, `removed` and the counts as before the
  // first.
  const TopoDS_Shape before = solid_->shape;
  const double volume = volume_;
  const int faces = faces_;
  const int off = removal_volumes_off_;
  const int replaced = removal_volumes_replaced_;
  const int mended = cuts_from_mended_stock_;
  const double worst = worst_removal_volume_;
  const std::size_t recorded = removed != nullptr ? removed->size() : 0;
  try {
    double taken = 0.0;
    for (const Solid& part : parts) taken += cut(part, removed, merge_faces);
    return taken;
  } catch (...) {
    solid_->shape = before;
    volume_ = volume;
    faces_ = faces;
    removal_volumes_off_ = off;
    removal_volumes_replaced_ = replaced;
    cuts_from_mended_stock_ = mended;
    worst_removal_volume_ = worst;
    if (removed != nullptr) removed->resize(recorded);
    throw;
  }
}

double BrepStock::cut_linear(const Cutter& cutter, const Vec3& start, const Vec3& end,
                             const Vec3& axis, std::vector<Solid>* removed) {
  Solid sweep;
  sweep.shape = linear_sweep_solid(cutter, start, end, axis);
  return cut(sweep, removed);
}

double BrepStock::cut_planar_arc(const Cutter& cutter, const Move& arc,
                                 std::vector<Solid>* removed) {
  return cut_all(solids(planar_arc_sweep_solids(cutter, arc)), removed);
}

double BrepStock::cut_lines(const Cutter& cutter, const std::vector<Line>& lines,
                            std::vector<Solid>* removed) {
  std::vector<Solid> sweeps;
  sweeps.reserve(lines.size());
  for (const Line& line : lines) {
    sweeps.push_back({linear_sweep_solid(cutter, line.start, line.end, line.axis)});
  }
  const double taken = cut_all(sweeps, removed, /*merge_faces=*/false);
  ++moves_in_lines_;
  return taken;
}

double BrepStock::cut_lofted(const Cutter& cutter, const Move& move, double tolerance,
                             std::vector<Solid>* removed) {
  Aabb within = tight_bounds();
  within.inflate(tolerance);
  const LoftedSweep loft = lofted_sweep_parts(cutter, move, tolerance, within);
  // Not merged: the loft's faces share no surface with the stock's.
  const double taken = cut_all(solids(loft.solids), removed, /*merge_faces=*/false);
  ++moves_lofted_;
  worst_loft_deviation_ = std::max(worst_loft_deviation_, loft.deviation);
  return taken;
}

double BrepStock::cut_helix(const Cutter& cutter, const Move& helix, std::vector<Solid>* removed) {
  return cut_all(solids(helix_sweep_solids(cutter, helix)), removed);
}

double BrepStock::cut_tilt(const Cutter& cutter, const Move& tilt, std::vector<Solid>* removed) {
  return cut_all(solids(tilt_sweep_solids(cutter, tilt)), removed);
}

double BrepStock::cut(const Solid& cutter, std::vector<Solid>* removed) {
  return cut(cutter, removed, /*merge_faces=*/true);
}

double BrepStock::cut(const Solid& cutter, std::vector<Solid>* removed, bool merge_faces) {
  const OcctFloatingPoint occt;
  if (box_of(cutter.shape).IsOut(box_of(solid_->shape))) return 0.0;
  const double swept = shape_volume(cutter.shape);
  const Aabb box = bounds();
  const double size = box.is_empty() ? 1.0 : (box.max - box.min).norm();
  // BRepGProp integrates curved faces numerically: a relative 1e-7 of the stock is far above
  // its error and far below any chip.
  const double slack = 1e-7 * std::max(volume_, 1.0);
  // With OpenCASCADE's fuzzy option first (faces within 1e-6 of the stock's size taken as
  // touching: a zigzag's ends against the walls earlier passes left at the tool's radius leave
  // slivers of 1e-10 mm² otherwise, and FreeCAD's pocket failed on its third level; with it the
  // whole program runs, its volume within 0.01 % of the dexel workpiece's), then as it is, then
  // with 1e-5 of the size: a bull nose's second-level plunge where its first level's loop
  // closed, the tool's faces on the stock's, took nothing with the first two (refused by
  // tool_left_material) and was cut right with the third. It stays a tenth of that check's depth.
  const double fuzzy_values[] = {1e-6 * size, 0.0, 1e-5 * size};
  // Each refused attempt's fuzzy value and why it was refused, in turn.
  struct Failure {
    double fuzzy = 0.0;
    bool mended = false;  // cut from the mended stock
    std::string why;
  };
  std::vector<Failure> failures;
  // A result may hold edges whose tolerance OpenCASCADE raised, by up to 0.05 mm on the bundled
  // example's 5-axis pass (a 125 mm stock) and FreeCAD's two-tool program (78 mm). A 6 mm bull
  // nose's straight move after a corner at its radius gave a face of no width bounded by one
  // edge of tolerance 3 mm, a valid solid by BRepCheck and the right volume; the next cut's
  // face-face intersection on it never finished (IntPatch_Intersection::CheckSingularPoints
  // stepping along that edge by a step too small to move its parameter). A result whose
  // tolerance exceeds its inputs' by more than 1e-3 of the stock's size (at least 0.1 mm: one
  // cut raised them by up to 0.03 mm on those solids) is refused. Raises that pass add up over a
  // run; what this stops is one cut's jump.
  const double inputs_tolerance =
      std::max(max_tolerance(solid_->shape), max_tolerance(cutter.shape));
  const double tolerance_allowed = inputs_tolerance + std::max(1e-3 * size, 0.1);
  // An attempt that passed the stock's checks: the cut stock, its volume, what it took and the
  // solids the engagement reads.
  struct Attempt {
    TopoDS_Shape result;
    double after = 0.0, taken = 0.0;
    std::vector<Solid> took;
  };
  // Keeps an attempt: its same-domain faces merged where that keeps the solid (below), `took`
  // appended to `removed`; returns the volume removed.
  const auto keep = [&](Attempt kept) {
    TopoDS_Shape& result = kept.result;
    double& after = kept.after;
    // Same-domain faces merged (a slot's floor pieces, one per cut, become one face), only on a
    // cut that passed the checks, and only where that keeps the solid: valid, with its volume.
    // Where OpenCASCADE cannot merge them, or the merge changes the solid, the cut as it is: the
    // bundled example's retract from its circle, the tool tangent to both walls the helix left,
    // split a wall along the tangent, and merging it back gave a valid solid 546 mm³ larger; and
    // on a cut that had gone wrong (a helix's last piece, without the fuzzy value, taking
    // nothing) the merge never finished, its memory growing by gigabytes. Not for a move's
    // linear pieces (merge_faces false): on a 5-axis move's the merge had not finished after 15
    // CPU minutes, and each piece has its own axis, so its faces rarely share a surface with the
    // stock's. (Without any merging, a face of FreeCAD's pocket could not be tessellated.)
    if (merge_faces) {
      try {
        ShapeUpgrade_UnifySameDomain unify(result, true, true, true);
        unify.Build();
        const TopoDS_Shape merged = unify.Shape();
        const double merged_volume = shape_volume(merged);
        if (std::abs(merged_volume - after) <= slack &&
            max_tolerance(merged) <= tolerance_allowed && BRepCheck_Analyzer(merged).IsValid()) {
          result = merged;
          after = merged_volume;
        }
      } catch (const Standard_Failure&) {
      }
    }
    if (removed != nullptr) {
      std::move(kept.took.begin(), kept.took.end(), std::back_inserter(*removed));
    }
    solid_->shape = result;
    volume_ = after;
    faces_ = count_faces(result);
    return std::max(0.0, kept.taken);
  };
  // The first attempt that passed every check of the stock but whose removal volume did not hold
  // what the stock lost: kept in case no attempt gives both (see below).
  std::optional<Attempt> stock_only;
  // A cut never adds material, yet OpenCASCADE's cut of a 6 mm bull nose's ring round each
  // corner of a loop at radius 2.5 (below the tool's radius 3) made the stock grow by 5e-5 to
  // 4e-4 mm³ (within the volume check's slack) and left the corner's spike whole, with every
  // fuzzy value, where the ring takes a sliver of 0.006 mm³ of it (a point oracle of the
  // program's poses says 0.0063 at the closing corner). The same cut from the stock mended by
  // ShapeFix_Shape takes it: 0.0063. So an attempt that makes the stock grow by more than 1e-10
  // of it (far above the volumes' rounding: a cut that takes nothing leaves it at 0), or that
  // leaves a solid inside the swept volume (solid_inside_tool), is suspect, and after the fuzzy
  // values the cut is tried again from the mended stock.
  const double growth = 1e-10 * std::max(volume_, 1.0);
  bool suspect = false;  // an attempt grew the stock or left a solid inside the swept volume
  // The first attempt that grew the stock (by less than the slack) but passed every other
  // check: kept where no attempt passes them all, as before this check (FreeCAD's pocket, line
  // 153, a retract straight up along the pocket's walls, which takes nothing: the stock grew by
  // 1.8e-5 mm³ with every fuzzy value, from the mended stock too).
  std::optional<Attempt> grown;
  std::optional<TopoDS_Shape> mended;
  const std::pair<bool, double> attempts[] = {{false, fuzzy_values[0]}, {false, fuzzy_values[1]},
                                              {false, fuzzy_values[2]}, {true, fuzzy_values[0]},
                                              {true, fuzzy_values[1]},  {true, fuzzy_values[2]}};
  for (const auto& [from_mended, fuzzy] : attempts) {
    if (from_mended && !suspect) break;
    const auto fail = [&, mended_stock = from_mended, value = fuzzy](std::string why) {
      failures.push_back({value, mended_stock, std::move(why)});
    };
    try {
      if (from_mended && !mended) mended = mended_copy(solid_->shape);
      const TopoDS_Shape& stock = from_mended ? *mended : solid_->shape;
      BRepAlgoAPI_Cut cut;
      run_boolean(cut, stock, cutter.shape, fuzzy);
      if (!cut.IsDone() || cut.HasErrors()) {
        fail("BRepAlgoAPI_Cut reported an error");
        continue;
      }
      // With the engagement, a copy: the removal volume's common below is built on the same
      // intersection and shares its split edges and faces, and building it altered them in the
      // stock kept. On FreeCAD's two-tool program cut down to a slot and the bull nose's first
      // two levels, the cuts that followed then differed from a run without the engagement (the
      // last corner of the first level took 0.036 mm³ instead of 0.0066), and the second
      // level's last corner was refused (exit 3): its removal volume held nothing.
      TopoDS_Shape result =
          removed != nullptr ? BRepBuilderAPI_Copy(cut.Shape()).Shape() : cut.Shape();
      if (!BRepCheck_Analyzer(result).IsValid()) {
        fail("the result is not a valid solid (BRepCheck)");
        continue;
      }
      if (const double tolerance = max_tolerance(result); tolerance > tolerance_allowed) {
        fail(fmt::format(
            "the result has an edge or vertex of tolerance {:g} mm, its inputs' at most {:g}",
            tolerance, inputs_tolerance));
        continue;
      }
      double after = shape_volume(result);
      const double taken = volume_ - after;
      if (taken < -slack || taken > swept + slack) {
        if (taken < 0.0) suspect = true;
        fail(
            fmt::format("the stock's volume changed by {:g} mm³, outside [0, {:g}] mm³ "
                        "(the swept volume's)",
                        -taken, swept));
        continue;
      }
      // Deeper than 1e-4 of the stock's size (the diagonal of its box: 17 µm on a 100 mm cube),
      // far above the fuzzy value and the faces' tolerances.
      if (tool_left_material(result, cutter.shape, 1e-4 * size)) {
        fail("points inside the swept volume are still inside the stock after the cut");
        continue;
      }
      if (solid_inside_tool(result, cutter.shape)) {
        suspect = true;
        fail("a solid of the result lies inside the swept volume");
        continue;
      }
      std::vector<Solid> took;
      if (removed != nullptr) {
        // The removal volume from the same intersection (the cut's pave filler): its volume
        // must be what the stock lost.
        BRepAlgoAPI_Common common(stock, cutter.shape, *cut.DSFiller());
        double in_rv =
            common.IsDone() && !common.HasErrors() ? solids_of(common.Shape(), took) : -1.0;
        if (std::abs(in_rv - taken) > slack + 1e-4 * taken) {
          // Where it is not (it has come out empty, on the last piece of a helix and on a
          // 5-axis move's linear pieces), a common of its own with a copy of the tool (its
          // geometry too): on the helix's piece a common of its own with the tool itself came
          // out empty as well, and with the copy it held what the stock lost. (The stock holds
          // faces of the pieces cut before, built like this one.)
          BRepAlgoAPI_Common again;
          run_boolean(again, stock, BRepBuilderAPI_Copy(cutter.shape).Shape(), fuzzy);
          std::vector<Solid> own;
          const double own_rv =
              again.IsDone() && !again.HasErrors() ? solids_of(again.Shape(), own) : -1.0;
          if (std::abs(own_rv - taken) < std::abs(in_rv - taken)) {
            took = std::move(own);
            in_rv = own_rv;
          }
        }
        // It serves the engagement only: within 1e-4 of the cut it is taken as it is (on a
        // helix's pipe shells OpenCASCADE's common has been seen 4e-5 off a cut that every
        // fuzzy value agrees on); up to 1 % off it is taken and counted (removal_volumes_off:
        // the bundled example's circle along the walls its helical entry's linear pieces left
        // gave 0.6 %); beyond, the next attempt is tried, and where none holds it the
        // engagement reads the stock before the cut (below).
        const double off = std::abs(in_rv - taken);
        if (off > slack + 1e-2 * taken || refuse_removal_volumes_) {
          fail(in_rv < 0.0
                   ? "BRepAlgoAPI_Common (the removal volume) reported an error"
                   : fmt::format(
                         "the removal volume holds {:g} mm³ where the stock lost {:g} mm³{}", in_rv,
                         taken, refuse_removal_volumes_ ? " (refused by a test)" : ""));
          if (!stock_only) stock_only = Attempt{result, after, taken, {}};
          continue;
        }
        if (off > slack + 1e-4 * taken) {
          ++removal_volumes_off_;
          worst_removal_volume_ = std::max(worst_removal_volume_, off / taken);
        }
      }
      if (taken < -growth) {
        suspect = true;
        fail(fmt::format("the stock grew by {:g} mm³", -taken));
        if (!grown) grown = Attempt{result, after, taken, std::move(took)};
        continue;
      }
      if (from_mended) ++cuts_from_mended_stock_;
      return keep({result, after, taken, std::move(took)});
    } catch (const Standard_Failure& e) {
      fail(fmt::format("OpenCASCADE failed ({}: {})", e.DynamicType()->Name(),
                       e.GetMessageString()));
    }
  }
  // Every attempt grew the stock or failed: the first that only grew it, as before the check.
  if (grown) return keep(std::move(*grown));
  if (stock_only) {
    // No attempt gave a removal volume that holds what the stock lost, but one cut the stock
    // right by every check of the stock: it is kept, as a run without the engagement keeps it
    // (merged alike, so both runs go on with the same stock), and the engagement reads a copy of
    // the stock before the cut instead. At a location, a point just outside the cutter where it
    // moves into the material (the only points the engagement tests) lies in the swept volume,
    // so it lies in W ∩ SV exactly when it lies in W. They differ only where the tool does not
    // reach the circle read (2e-7 mm outside it) before the move ends: within √(2·2e-7/ρ) of a
    // line the move grazes (f = 0), where the stock counts material the RV does not. The removal
    // volume is only the smaller solid to read. Seen on FreeCAD's two-tool program, line 142
    // (the third level's first corner, whose own sweep OpenCASCADE's union refused, cut as its
    // linear pieces): a piece's removal volume held 0.238 mm³ where the stock lost 0.028, with
    // every fuzzy value; the engagement read from the stock there agrees with the dexel
    // workpiece's.
    stock_only->took = {{BRepBuilderAPI_Copy(solid_->shape).Shape()}};
    ++removal_volumes_replaced_;
    return keep(std::move(*stock_only));
  }
  std::string tried;
  for (std::size_t k = 0; k < failures.size(); ++k) {
    const auto& [fuzzy, from_mended, why] = failures[k];
    tried += fmt::format("{}({}) {}{}: {}", k == 0 ? "" : "; ", k + 1,
                         from_mended ? "from the stock mended by ShapeFix, " : "",
                         fuzzy > 0.0 ? fmt::format("with a fuzzy value of {:g} mm", fuzzy)
                                     : std::string("without one"),
                         why);
  }
  throw ComputationError(fmt::format("B-rep removal: {}", tried));
}

}  // namespace cwe
