#include "cwe/engagement/brep_workpiece.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <BRepBndLib.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepIntCurveSurface_Inter.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <Bnd_Box.hxx>
#include <GeomAdaptor_Curve.hxx>
#include <Geom_Circle.hxx>
#include <IntCurvesFace_ShapeIntersector.hxx>
#include <Standard_Failure.hxx>
#include <gp_Ax2.hxx>
#include <gp_Lin.hxx>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/engagement/engagement_grid.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/workpiece/brep/brep_shapes.hpp"
#include "move_pieces.hpp"

namespace cwe {
namespace {

gp_Pnt to_pnt(const Vec3& p) { return gp_Pnt(p.x(), p.y(), p.z()); }
gp_Dir to_dir(const Vec3& d) { return gp_Dir(d.x(), d.y(), d.z()); }

// OpenCASCADE's intersectors and classifier of a part of a removal volume (they keep state).
struct Reader {
  BRepIntCurveSurface_Inter crossings;  // of circles
  IntCurvesFace_ShapeIntersector rays;  // of lines, each face's polyhedron made once
  BRepClass3d_SolidClassifier classifier;
};
// A reader for each part, each made when first needed.
using Readers = std::vector<std::optional<Reader>>;

// A move's removal volume RV = W ∩ SV as its cut found it (one or more solids; a helix's per
// piece), and the move's pieces for the test that a point was taken earlier on the move.
struct BrepRemoval {
  struct Part {
    TopoDS_Shape solid;
    Bnd_Box box;
  };
  std::vector<Part> parts;
  MovePieces pieces;

  // Readers kept for the move's later locations: a location's engagement takes a set (or a new
  // one) and gives it back, so a reader is made once per set, not at every location (4-5 % of
  // the engagement's time on the bundled example's helix and a bull-nose side cut).
  std::unique_ptr<Readers> take_readers() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (idle_.empty()) return std::make_unique<Readers>(parts.size());
    std::unique_ptr<Readers> readers = std::move(idle_.back());
    idle_.pop_back();
    return readers;
  }
  void give_back(std::unique_ptr<Readers> readers) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(std::move(readers));
  }

 private:
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<Readers>> idle_;
};

struct BrepStep : StepEngagement::Step {
  std::shared_ptr<const BrepRemoval> removed;
  std::size_t before = 0;  // the move's pieces wholly before the step (MovePieces::before)
};

// How close to a face a point or a crossing counts as on it, mm: OpenCASCADE's own precision
// (Precision::Confusion).
constexpr double kOnFace = 1e-7;

// The solid-model CWE (Aras 2008 §6.1): at a location, the engaged part of each band's circle
// (a disc or ring of the engagement grid) is where the circle, a hair outside the cutter, lies
// inside the move's RV and moves into the material (f > 0), and was not taken earlier on the
// move. The circle's crossings with the RV's faces (BRepIntCurveSurface_Inter, exact) and the
// roots of f cut it into arcs, each wholly in or out: its midpoint is classified by two rays'
// crossings, OpenCASCADE's solid classifier where they cannot decide (inside()). The intervals
// are exact up to OpenCASCADE's tolerances, not a grid's cells; a crossing OpenCASCADE misses at
// a tangency drops an island thinner than its tolerance.
class BrepStepEngagement : public StepEngagement {
 public:
  BrepStepEngagement(BrepWorkpiece& workpiece, const Cutter& cutter, double spacing,
                     const EngagementOptions& options)
      : workpiece_(workpiece), grid_(cutter, spacing, options) {
    covered_ = options.contact > 0.0 ? options.contact : spacing / 10.0;
  }

  std::unique_ptr<Step> new_step() const override { return std::make_unique<BrepStep>(); }

  bool removes_whole_moves() const override { return true; }

  double remove_move(const MoveSweep& sweep) override {
    std::vector<BrepStock::Solid> removed;
    const double volume = workpiece_.remove(sweep, &removed);
    auto record = std::make_shared<BrepRemoval>();
    record->pieces = MovePieces(sweep);
    for (BrepStock::Solid& solid : removed) {
      BrepRemoval::Part part{std::move(solid.shape), {}};
      // A coarse triangulation (0.05 mm, 0.5 rad) makes the boxes tight: without it a B-spline
      // face's box is its control points', and a helix's RV then met every disc's circle (five
      // times the circles read, and crossings with each face's box in them).
      BRepMesh_IncrementalMesh(part.solid, 0.05, false, 0.5, false);
      BRepBndLib::Add(part.solid, part.box, /*useTriangulation=*/true);
      part.box.Enlarge(kOnFace);
      record->parts.push_back(std::move(part));
    }
    move_removed_ = std::move(record);
    return volume;
  }

  // The move was removed whole (remove_move): a step only records its move's RV.
  double remove(const MoveSweep& sweep, Step* step) override {
    if (step != nullptr) {
      auto& record = static_cast<BrepStep&>(*step);
      record.removed = move_removed_;
      record.before = move_removed_ ? move_removed_->pieces.before(sweep) : 0;
    }
    return 0.0;
  }

  EngagementMap at(const ToolState& state, const Step& step) const override {
    const auto& record = static_cast<const BrepStep&>(step);
    std::vector<std::vector<Interval>> found(grid_.bands());
    if (record.removed && !record.removed->parts.empty()) {
      // OpenCASCADE's intersectors and classifiers keep state: a set of this call's own.
      std::unique_ptr<Readers> readers = record.removed->take_readers();
      try {
        for (std::size_t k = 0; k < found.size(); ++k) {
          found[k] = scan(*record.removed, record.before, *readers, state, grid_.band(k));
        }
        record.removed->give_back(std::move(readers));
      } catch (const Standard_Failure& e) {
        const Vec3& tip = state.tcs.origin;
        throw ComputationError(fmt::format(
            "B-rep engagement at the cutter location ({:.4f}, {:.4f}, {:.4f}): OpenCASCADE "
            "failed ({}: {})",
            tip.x(), tip.y(), tip.z(), e.DynamicType()->Name(), e.GetMessageString()));
      }
    }
    return grid_.map(std::move(found));
  }

 private:
  // Whether p lies inside a part of the RV. Two rays from p, along fixed directions, each
  // crossing the part's faces only through their interiors, not tangentially and none within
  // kNear of p, whose crossings agree in parity, decide it; otherwise (a ray along a face's
  // edge, p on a face, rays that disagree: a crossing missed) OpenCASCADE's solid classifier
  // does. It decides the same thing, but tests its ray against every edge near it by a global
  // search (BRepClass3d_SClassifier → Extrema_ExtCC), over 80 % of a bull-nose's run, whose
  // silhouette edges are B-splines.
  static bool inside(Reader& r, const Bnd_Box& box, const gp_Pnt& p) {
    static const std::array<gp_Dir, 3> kRays = {gp_Dir(0.5773, 0.6123, 0.5402),
                                                gp_Dir(-0.4127, 0.7071, -0.5742),
                                                gp_Dir(0.8105, -0.3306, 0.4836)};
    // Beyond the part's box from anywhere (callers give a p within it).
    const double far = std::sqrt(box.SquareExtent()) + box.Distance(Bnd_Box(p, p)) + 1.0;
    int votes = 0, odd = 0;
    for (const gp_Dir& direction : kRays) {
      r.rays.Perform(gp_Lin(p, direction), -kNear, far);
      if (!r.rays.IsDone()) continue;
      int crossed = 0;
      bool clean = true, on = false;
      for (int i = 1; clean && i <= r.rays.NbPnt(); ++i) {
        const double w = r.rays.WParameter(i);
        on = std::abs(w) <= kNear;
        clean =
            !on && r.rays.State(i) == TopAbs_IN && r.rays.Transition(i) != IntCurveSurface_Tangent;
        crossed += w > 0.0 ? 1 : 0;
      }
      if (on) break;  // p on a face (a circle along the stock's top, say): other rays meet it too
      if (!clean) continue;
      ++votes;
      odd += crossed % 2;
      if (votes == 2) {
        if (odd != 1) return odd == 2;
        break;
      }
    }
    r.classifier.Perform(p, kOnFace);
    return r.classifier.State() == TopAbs_IN;
  }
  // A crossing this close to the point classified leaves it undecided, mm.
  static constexpr double kNear = 10.0 * kOnFace;

  static Reader& reader(Readers& readers, const BrepRemoval& removed, std::size_t part) {
    std::optional<Reader>& r = readers[part];
    if (!r) {
      r.emplace();
      r->crossings.Load(removed.parts[part].solid, kOnFace);
      r->rays.Load(removed.parts[part].solid, kOnFace);
      r->classifier.Load(removed.parts[part].solid);
    }
    return *r;
  }

  std::vector<Interval> scan(const BrepRemoval& removed, std::size_t before, Readers& readers,
                             const ToolState& state, const EngagementGrid::Band& band) const {
    const EngagementGrid::Front front =
        EngagementGrid::front(band, state.tip_velocity_tcs(), state.angular_velocity_tcs());
    if (!front.moves) return {};
    const Frame& tcs = state.tcs;
    const Vec3 x = tcs.x(), y = tcs.y(), z = tcs.z();
    // The circle read: the band's, a hair outside the cutter along its normal.
    const double radius = band.rho + offset_ * band.normal.x();
    const Vec3 centre = tcs.origin + (band.z + offset_ * band.normal.y()) * z;
    const Aabb reach = EngagementGrid::circle_bounds(band, tcs, 2.0 * offset_);
    Bnd_Box circle_box;
    circle_box.Update(reach.min.x(), reach.min.y(), reach.min.z(), reach.max.x(), reach.max.y(),
                      reach.max.z());
    std::vector<std::size_t> near;
    for (std::size_t k = 0; k < removed.parts.size(); ++k) {
      if (!removed.parts[k].box.IsOut(circle_box)) near.push_back(k);
    }
    if (near.empty()) return {};

    // The arcs of the circle that move into the material (f > f_min), within [0, 2π]: φ runs
    // from the frame's y towards its x (the grid's convention), the circle's own parameter
    // about −z with y as its first axis.
    std::vector<Interval> arcs;
    const double amplitude = std::hypot(front.f.a, front.f.b);
    const double cosine = amplitude > 0.0 ? (front.f_min - front.f.c) / amplitude : 2.0;
    if (std::abs(cosine) < 1.0) {
      // f = A cos(φ − mid) + c: above f_min within `half` of mid.
      const double mid = std::atan2(front.f.a, front.f.b), half = std::acos(cosine);
      const double lo = mid - half - kTwoPi * std::floor((mid - half) / kTwoPi), hi = lo + 2 * half;
      arcs.push_back({lo, std::min(hi, kTwoPi)});
      if (hi > kTwoPi) arcs.push_back({0.0, hi - kTwoPi});
    } else if (front(0.0, 1.0)) {
      arcs.push_back({0.0, kTwoPi});
    }
    // Each arc cut where it crosses the RV's faces.
    const Handle(Geom_Circle) circle =
        new Geom_Circle(gp_Ax2(to_pnt(centre), to_dir(-z), to_dir(y)), radius);
    std::vector<double> ends;
    for (const Interval& arc : arcs) {
      ends.push_back(arc.lo);
      ends.push_back(arc.hi);
      const GeomAdaptor_Curve curve(circle, arc.lo, arc.hi);
      for (const std::size_t k : near) {
        BRepIntCurveSurface_Inter& crossings = reader(readers, removed, k).crossings;
        for (crossings.Init(curve); crossings.More(); crossings.Next()) {
          ends.push_back(std::clamp(crossings.W(), arc.lo, arc.hi));
        }
      }
    }
    std::sort(ends.begin(), ends.end());

    const auto engaged = [&](double phi) {
      const double s = std::sin(phi), c = std::cos(phi);
      if (!front(s, c)) return false;
      const Vec3 radial = s * x + c * y;
      const Vec3 q = centre + radius * radial;
      if (before > 0) {
        const Vec3 normal = band.normal.x() * radial + band.normal.y() * z;
        if (removed.pieces.swept_before(q, normal, before, covered_)) return false;
      }
      const gp_Pnt p = to_pnt(q);
      for (const std::size_t k : near) {
        if (removed.parts[k].box.IsOut(p)) continue;
        if (inside(reader(readers, removed, k), removed.parts[k].box, p)) return true;
      }
      return false;
    };
    std::vector<Interval> found;
    for (std::size_t k = 0; k + 1 < ends.size(); ++k) {
      const double lo = ends[k], hi = ends[k + 1];
      if (!(hi - lo > kArcTolerance) || !engaged(0.5 * (lo + hi))) continue;
      if (!found.empty() && lo - found.back().hi <= kArcTolerance) {
        found.back().hi = hi;
      } else {
        found.push_back({lo, hi});
      }
    }
    return found;
  }

  // Arcs shorter than this (radians) are not classified: the crossings that bound them are one.
  static constexpr double kArcTolerance = 1e-9;

  BrepWorkpiece& workpiece_;
  EngagementGrid grid_;
  // How far outside the cutter surface the circles lie, mm: off the cutter's own faces (the
  // RV's leading faces at the move's end), and little enough that where a wall the move leaves
  // grazes the cutter (f = 0), the circle enters it within √(2·(offset + kOnFace)/ρ) ≈ 0.02° of
  // the grazing line at ρ = 5.
  static constexpr double offset_ = 2.0 * kOnFace;
  double covered_ = 0.0;  // how deep inside an earlier piece a point was taken before, mm
  std::shared_ptr<const BrepRemoval> move_removed_;
};

}  // namespace

BrepWorkpiece::BrepWorkpiece(BrepStock& stock, double spacing)
    : stock_(stock), cell_(1e-7 * std::max(stock.volume(), 1.0)), spacing_(spacing) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(
        fmt::format("B-rep workpiece: resolution {} mm, expected a positive length", spacing));
  }
}

double BrepWorkpiece::remove(const MoveSweep& sweep, std::vector<BrepStock::Solid>* removed) {
  const Move& move = sweep.move();
  const ConvexParts& parts = sweep.parts();
  if (parts.parts().size() != 1 || parts.parts().front().offset != 0.0) {
    throw ComputationError(
        "B-rep removal: the cutter's profile has a concave part; the B-rep workpiece sweeps "
        "convex cutters (every APT cutter)");
  }
  const Cutter& cutter = *parts.parts().front().cutter;
  const Vec3 axis = move.start_axis.normalized();
  const bool constant_axis = move.axis_angle() <= tol::kAngle;
  if (!move.is_arc() && constant_axis) {
    return stock_.cut_linear(cutter, move.start, move.end, axis, removed);
  }
  // The pieces [first, last) whose tool can come within a clearance of the stock: every point of
  // the true motion lies within the deviation bound of a piece's sweep, of the same stretch of
  // the move, so beyond them the move cuts nothing. A retract that turns the axis on its way up
  // (the CATIA program's last rapid: 90 mm up, 1,316 pieces) comes near the stock over its first
  // 136. The clearance (the tool's radius, at least 1 mm) keeps the ends of what is cut clear of
  // the stock: trimmed to the stock's box itself, the bundled example's 5-axis pass started its
  // loft with the tool touching the block's side, and the stock's tessellation no longer
  // closed. Found once, when a cut needs them (the stock's tight box is not free).
  const std::vector<LinearSweep>& pieces = sweep.pieces();
  std::size_t first = 0, last = 0;
  bool found = false;
  const auto find_reaching = [&] {
    if (found) return;
    found = true;
    Aabb stock_box = stock_.tight_bounds();
    const double clearance = std::max(1.0, cutter.bounding_cylinder().radius);
    stock_box.inflate(sweep.deviation_bound() + clearance);
    first = 0;
    last = pieces.size();
    while (first < last && !pieces[first].bounds().intersects(stock_box)) ++first;
    while (last > first && !pieces[last - 1].bounds().intersects(stock_box)) --last;
  };
  // Anything else (an arc with the tool off its normal, and what the sweeps below refuse): the
  // move's linear pieces, each with the mean of its ends' axes (MoveSweep: the motion within the
  // sweep tolerance, its deviation_bound in the summary), each swept exactly.
  const auto in_lines = [&] {
    find_reaching();
    if (first == last) return 0.0;
    std::vector<BrepStock::Line> lines;
    lines.reserve(last - first);
    for (std::size_t k = first; k < last; ++k) {
      lines.push_back({pieces[k].start(), pieces[k].end(), pieces[k].axis().normalized()});
    }
    return stock_.cut_lines(cutter, lines, removed);
  };
  // A move whose own sweep cannot be built or cut is cut as its linear pieces, within the sweep
  // tolerance like any other move; the stock is as before the move (cuts are all or none). If
  // those fail too, both reasons are given.
  const auto or_in_lines = [&](const auto& cut) {
    try {
      return cut();
    } catch (const ComputationError& own) {
      try {
        return in_lines();
      } catch (const ComputationError& lines) {
        throw ComputationError(
            fmt::format("{}; as its linear pieces: {}", own.what(), lines.what()));
      }
    }
  };
  if (move.is_arc() && constant_axis &&
      std::abs(axis.dot(move.normal.normalized())) > 1.0 - 1e-12) {
    // Arcs refused: a helix narrower than the tool; a ball end's helix going up, whose sewn
    // faces do not close; a bull-nose's, whose ruled sheets can miss the volume check by 1e-5.
    return or_in_lines([&] {
      return move.axial == 0.0 ? stock_.cut_planar_arc(cutter, move, removed)
                               : stock_.cut_helix(cutter, move, removed);
    });
  }
  if (!move.is_arc() && (move.end - move.start).norm() <= tol::kLength) {
    // A tilt in place: the tool's ends, meridian section and top disc revolved (exact).
    return or_in_lines([&] { return stock_.cut_tilt(cutter, move, removed); });
  }
  if (!move.is_arc()) {
    // A simultaneous 5-axis line, lofted through its poses within the sweep tolerance; refused
    // where its silhouettes change their kind or are off the sweep (lofted_sweep_solid). Only
    // its stretch over the pieces that can meet the stock: lofted whole and then as its 1,316
    // linear pieces, the CATIA program's retract took 3 min to be refused.
    find_reaching();
    if (first == last) return 0.0;
    const auto n = static_cast<double>(pieces.size());
    const double u0 = static_cast<double>(first) / n, u1 = static_cast<double>(last) / n;
    const Move reaching = first == 0 && last == pieces.size() ? move : move.part(u0, u1);
    return or_in_lines(
        [&] { return stock_.cut_lofted(cutter, reaching, parts.tolerance(), removed); });
  }
  return in_lines();
}

std::vector<double> BrepWorkpiece::remove(std::span<const MoveSweep> sweeps) {
  std::vector<double> volumes;
  volumes.reserve(sweeps.size());
  for (std::size_t k = 0; k < sweeps.size(); ++k) {
    try {
      volumes.push_back(remove(sweeps[k]));
    } catch (const ComputationError& e) {
      throw ComputationError(k, e.what());
    }
  }
  return volumes;
}

std::unique_ptr<StepEngagement> BrepWorkpiece::engagement(const Cutter& cutter,
                                                          const EngagementOptions& options) {
  return std::make_unique<BrepStepEngagement>(*this, cutter, spacing_, options);
}

}  // namespace cwe
