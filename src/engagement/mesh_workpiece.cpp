#include "cwe/engagement/mesh_workpiece.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/engagement/engagement_grid.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/geometry/mesh_sections.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "move_pieces.hpp"

namespace cwe {
namespace {

// The faceted tool the sweeps are made of (linear_piece_mesh), read along the engagement grid's
// circles: a cell is tested on the faceted surface, whose own sweep made the walls the move
// leaves, so that a grazing line (the side of a slot) is found where the faceted tool grazes
// its own wall, not half a facet angle inside it where the true circle leaves the faceted wall.
class FacetedTool {
 public:
  FacetedTool(const Cutter& cutter, double facet_depth, const EngagementGrid& grid) {
    if (!is_convex(cutter)) return;  // not a hull: read on the true surface
    const TriangleMesh hull = convex_hull(tool_surface_points(cutter, 2.0 * facet_depth));
    for (std::size_t k = 0; k < grid.discs().size(); ++k) {
      const double z = grid.discs()[k].z;
      std::vector<Plane> planes;
      for (const auto& t : hull.triangles) {
        const Vec3& a = hull.vertices[static_cast<std::size_t>(t[0])];
        const Vec3& b = hull.vertices[static_cast<std::size_t>(t[1])];
        const Vec3& c = hull.vertices[static_cast<std::size_t>(t[2])];
        if (std::min({a.z(), b.z(), c.z()}) > z || std::max({a.z(), b.z(), c.z()}) < z) continue;
        const Vec3 n = (b - a).cross(c - a);
        if (!(n.norm() > 0.0)) continue;
        planes.push_back({n.normalized(), n.normalized().dot(a)});
      }
      discs_.push_back(std::move(planes));
    }
  }
  bool empty() const { return discs_.empty(); }
  // The distance from the axis to the faceted surface at disc `disc`'s height, along the
  // horizontal unit direction `along` of the facets' frame; `fallback` (the true radius) if no
  // face lies that way (a disc outside the hull's heights, which the grid never samples).
  double radius(std::size_t disc, double z, const Vec3& along, double fallback) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Plane& p : discs_[disc]) {
      const double towards = p.normal.dot(along);
      if (towards > 0.0) best = std::min(best, (p.offset - p.normal.z() * z) / towards);
    }
    return std::isfinite(best) ? best : fallback;
  }

 private:
  struct Plane {
    Vec3 normal;    // outward unit normal
    double offset;  // normal · point
  };
  std::vector<std::vector<Plane>> discs_;  // the hull's faces spanning each disc's height
};

// A move's removal volume, with its sections by the planes normal to the tool axis when the
// axis is the same all along the move (3-axis and 3+2 moves): there, the cells of a disc are read
// in the disc's plane (MeshSection, 2-D), else by a point-inside query in 3-D (MeshRegion).
struct MoveRemoval {
  MoveRemoval(const TriangleMesh& mesh, const MoveSweep& sweep) : region(mesh), pieces(sweep) {
    if (pieces.axis() && !mesh.empty()) {
      slicer.emplace(mesh, Frame::from_z(Vec3::Zero(), *pieces.axis(), Vec3::UnitX()));
    }
  }
  MeshRegion region;
  std::optional<MeshSlicer> slicer;
  MovePieces pieces;
};

// A step's record: the removal volume of the move it lies on (shared by the move's steps).
struct MeshStep : StepEngagement::Step {
  std::shared_ptr<const MoveRemoval> removed;
  std::size_t before = 0;  // the move's pieces wholly before the step (MoveRemoval::pieces)
};

class MeshStepEngagement : public StepEngagement {
 public:
  MeshStepEngagement(MeshWorkpiece& workpiece, const Cutter& cutter, double spacing,
                     const EngagementOptions& options)
      : workpiece_(workpiece),
        grid_(cutter, spacing, options),
        faceted_(cutter, MeshWorkpiece::facet_depth(cutter, workpiece.facet()), grid_) {
    const double contact = options.contact > 0.0 ? options.contact : spacing / 10.0;
    offset_ = contact / 1000.0;
    // Q lies on the faceted surface, up to h inside the true tool, and an arc's chords within
    // tolerance/2 ≤ contact of it: an earlier piece's true tool covers a Q the step cuts by less
    // than h + contact.
    covered_ = MeshWorkpiece::facet_depth(cutter, workpiece.facet()) + contact;
  }

  std::unique_ptr<Step> new_step() const override { return std::make_unique<MeshStep>(); }

  bool removes_whole_moves() const override { return true; }

  double remove_move(const MoveSweep& sweep) override {
    TriangleMesh removed;
    const double volume = workpiece_.remove(sweep, &removed);
    move_removed_ = std::make_shared<const MoveRemoval>(removed, sweep);
    return volume;
  }

  // The move's parts were removed with it (remove_move): a step only records its move's RV.
  double remove(const MoveSweep& sweep, Step* step) override {
    if (step != nullptr) {
      auto& record = static_cast<MeshStep&>(*step);
      record.removed = move_removed_;
      record.before = move_removed_ ? move_removed_->pieces.before(sweep) : 0;
    }
    return 0.0;
  }

  EngagementMap at(const ToolState& state, const Step& step) const override {
    const std::shared_ptr<const MoveRemoval>& removed = static_cast<const MeshStep&>(step).removed;
    std::vector<std::vector<Interval>> found(grid_.bands());
    if (removed && !removed->region.empty()) {
      const Vec3 v = state.tip_velocity_tcs(), w = state.angular_velocity_tcs();
      // The facets' frame at this location (linear_piece_mesh's: x as close to world X as the
      // axis allows).
      const Frame facets = Frame::from_z(state.tcs.origin, state.tcs.z(), Vec3::UnitX());
      const std::size_t before = static_cast<const MeshStep&>(step).before;
      for (std::size_t k = 0; k < found.size(); ++k) {
        found[k] = scan(*removed, before, state, facets, k, v, w);
      }
    }
    return grid_.map(std::move(found));
  }

 private:
  // A cell P (f > 0) is engaged when the point Q a hair outside it along its normal lies in
  // the move's removal volume and in none of the move's pieces before the step (deeper than the
  // facets' depth plus the contact tolerance): on a linear piece Q is outside every earlier
  // position of the tool (the tool is convex and P's side moves into the material), so material the
  // move removes there is still to be cut; a curved move may have passed over Q before (a helix's
  // turn above). Q is read in the section of the RV by Q's plane normal to the axis when the move
  // has sections along this axis, else in 3-D.
  std::vector<Interval> scan(const MoveRemoval& removed, std::size_t before, const ToolState& state,
                             const Frame& facets, std::size_t index, const Vec3& v_tcs,
                             const Vec3& w_tcs) const {
    const EngagementGrid::Band& band = grid_.band(index);
    const bool on_facets = !band.ring && !faceted_.empty();
    const Frame& tcs = state.tcs;
    const Vec3 x = tcs.x(), y = tcs.y(), z = tcs.z();
    const Vec3 centre = tcs.origin + band.z * z;
    if (!EngagementGrid::circle_bounds(band, tcs, offset_).intersects(removed.region.bounds())) {
      return {};
    }
    const EngagementGrid::Front front = EngagementGrid::front(band, v_tcs, w_tcs);
    if (!front.moves) return {};
    // Q's distance from the axis along the radial direction whose components in the facets'
    // frame are (ru, rv).
    const auto reach = [&](double ru, double rv) {
      const double rho =
          on_facets ? faceted_.radius(index, band.z, Vec3(ru, rv, 0.0), band.rho) : band.rho;
      return rho + offset_ * band.normal.x();
    };
    // Q itself, in world coordinates, and whether a piece of the move before the step took it
    // (deeper than covered_ along the cell's normal).
    const auto point = [&](double s, double cs) -> Vec3 {
      const Vec3 radial = s * x + cs * y;
      const Vec3 local = facets.direction_to_local(radial);
      return centre + reach(local.x(), local.y()) * radial + offset_ * band.normal.y() * z;
    };
    const auto taken = [&](double s, double cs, const Vec3& q) {
      if (before == 0) return false;
      const Vec3 normal = band.normal.x() * (s * x + cs * y) + band.normal.y() * z;
      return removed.pieces.swept_before(q, normal, before, covered_);
    };
    if (removed.slicer && removed.slicer->frame().z().dot(z) > MovePieces::kSameAxis) {
      // In the plane of Q's height, in the slicer's (u, v): the facets' frame up to the origin.
      const Frame& plane = removed.slicer->frame();
      const Vec3 c = plane.to_local(centre);
      const MeshSection section = removed.slicer->section(c.z() + offset_ * band.normal.y());
      if (section.empty()) return {};
      const Vec2 xu(x.dot(plane.x()), x.dot(plane.y())), yu(y.dot(plane.x()), y.dot(plane.y()));
      const auto engaged = [&](double s, double cs) {
        if (!front(s, cs)) return false;
        const Vec2 r = s * xu + cs * yu;
        const double d = reach(r.x(), r.y());
        if (!section.contains(c.x() + d * r.x(), c.y() + d * r.y())) return false;
        return !taken(s, cs, point(s, cs));
      };
      return grid_.intervals(front, engaged);
    }
    const auto engaged = [&](double s, double cs) {
      if (!front(s, cs)) return false;
      const Vec3 q = point(s, cs);
      return removed.region.contains(q) && !taken(s, cs, q);
    };
    return grid_.intervals(front, engaged);
  }

  MeshWorkpiece& workpiece_;
  EngagementGrid grid_;
  FacetedTool faceted_;
  double offset_ = 0.0;   // how far outside the cutter surface Q lies, mm
  double covered_ = 0.0;  // how deep inside an earlier piece Q was taken before, mm
  std::shared_ptr<const MoveRemoval> move_removed_;
};

}  // namespace

MeshWorkpiece::MeshWorkpiece(MeshStock& stock, double facet, double spacing)
    : stock_(stock), facet_(facet), spacing_(spacing) {
  if (!(facet > 0.0) || !std::isfinite(facet)) {
    throw InputError(
        fmt::format("mesh workpiece: facet size {} mm, expected a positive length", facet));
  }
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(
        fmt::format("mesh workpiece: resolution {} mm, expected a positive length", spacing));
  }
}

double MeshWorkpiece::facet_depth(const Cutter& cutter, double facet) {
  const double r = cutter.profile().max_radius();
  const double half = 0.5 * facet;
  return half >= r ? r : r - std::sqrt(r * r - half * half);
}

double MeshWorkpiece::cell_volume() const { return std::pow(spacing_, 3); }

TriangleMesh MeshWorkpiece::piece_mesh(const LinearSweep& piece) const {
  // tool_surface_points keeps its chords within half the tolerance it is given.
  const std::vector<Vec3> tool =
      tool_surface_points(piece.cutter(), 2.0 * facet_depth(piece.cutter(), facet_));
  return linear_piece_mesh(tool, piece.start(), piece.end(), piece.axis());
}

double MeshWorkpiece::remove(const MoveSweep& sweep, TriangleMesh* removed) {
  // A planar arc of a tool of revolution: the tool's section revolved (one mesh, or a wedge and
  // the tool at both ends), not linear pieces.
  const ConvexParts& parts = sweep.parts();
  if (parts.parts().size() == 1 && parts.parts().front().offset == 0.0) {
    const Cutter& cutter = *parts.parts().front().cutter;
    const std::vector<TriangleMesh> arc = planar_arc_sweep(
        cutter, 2.0 * facet_depth(cutter, facet_), parts.tolerance(), sweep.move());
    if (!arc.empty()) return stock_.subtract(arc, removed);
  }
  std::vector<TriangleMesh> pieces;
  pieces.reserve(sweep.pieces().size());
  const Move& move = sweep.move();
  if (move.axis_angle() > tol::kAngle) {
    // A turning axis: each piece the hull of its two end tools in their own poses (not the
    // LinearSweep's mean axis, whose tool at a joint reaches up to reach·Δ/2 beyond the true
    // one and would take material the next move's first location is still to cut).
    std::vector<std::vector<Vec3>> tools;
    for (const ConvexParts::Part& part : parts.parts()) {
      tools.push_back(tool_surface_points(*part.cutter, 2.0 * facet_depth(*part.cutter, facet_)));
    }
    const int steps = sweep.path_pieces();
    for (int k = 0; k < steps; ++k) {
      const double u0 = static_cast<double>(k) / steps, u1 = static_cast<double>(k + 1) / steps;
      const Vec3 a0 = move.axis(u0), a1 = move.axis(u1);
      const Vec3 p0 = k == 0 ? move.start : move.position(u0);
      const Vec3 p1 = k + 1 == steps ? move.end : move.position(u1);
      for (std::size_t j = 0; j < tools.size(); ++j) {
        const double offset = parts.parts()[j].offset;
        pieces.push_back(linear_piece_mesh(tools[j], p0 + offset * a0, a0, p1 + offset * a1, a1));
      }
    }
    return stock_.subtract(pieces, removed);
  }
  for (const LinearSweep& piece : sweep.pieces()) pieces.push_back(piece_mesh(piece));
  return stock_.subtract(pieces, removed);
}

std::vector<double> MeshWorkpiece::remove(std::span<const MoveSweep> sweeps) {
  std::vector<double> volumes;
  volumes.reserve(sweeps.size());
  for (std::size_t k = 0; k < sweeps.size(); ++k) {
    try {
      volumes.push_back(remove(sweeps[k], nullptr));
    } catch (const ComputationError& e) {
      throw ComputationError(k, e.what());
    }
  }
  return volumes;
}

std::unique_ptr<StepEngagement> MeshWorkpiece::engagement(const Cutter& cutter,
                                                          const EngagementOptions& options) {
  return std::make_unique<MeshStepEngagement>(*this, cutter, spacing_, options);
}

}  // namespace cwe
