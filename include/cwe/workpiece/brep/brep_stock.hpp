#pragma once
// The in-process workpiece as an exact solid (OpenCASCADE B-rep): the thesis's reference
// representation (Aras 2008 §6.1). Each move's swept volume is built exactly
// (cwe/workpiece/brep/brep_shapes.hpp) and cut from the solid with BRepAlgoAPI_Cut, with a fuzzy
// value of 1e-6 of the stock's size (near-coincident faces taken as touching, so that cuts along
// walls earlier passes left leave no slivers); after every cut the solid must be valid
// (BRepCheck), have lost between 0 and the swept volume's volume, keep no point well inside the
// tool, no solid of its own inside the swept volume and no edge whose tolerance jumped, else the
// cut is tried again without the fuzzy value, then with 1e-5 of the size; where an attempt made
// the stock grow or left a solid inside the swept volume, the three are tried again from the
// stock mended by ShapeFix_Shape; then the move is refused (ComputationError): a run never goes
// on with a broken solid. The booleans leave their arguments as they were (non-destructive).
//
// OpenCASCADE's types stay behind this header; cwe/workpiece/brep/brep_shapes.hpp gives the
// solid itself to the code that needs it (STEP output, tessellation, tests). The members defined
// out of line are in the OpenCASCADE module (libcwe-occt, cwe/io/occt.hpp): code outside it
// makes a stock with brep_stock (cwe/io/step.hpp) and cuts it through its Workpiece
// (brep_workpiece); what is inline here works everywhere.

#include <memory>
#include <vector>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe {

class BrepStock {
 public:
  // A box. Throws InputError for a box of no volume.
  static BrepStock from_box(const Aabb& box);

  BrepStock(BrepStock&&) noexcept = default;
  BrepStock& operator=(BrepStock&&) noexcept = default;
  ~BrepStock() = default;

  struct Solid;  // the OpenCASCADE shape (brep_shapes.hpp)

  // Cuts the volume the cutter sweeps along a line with a constant axis (3-axis and 3+2 moves;
  // linear_sweep_solid) and returns the volume removed, mm³. Throws ComputationError when the
  // sweep cannot be built or the cut fails its checks; the stock is then unchanged. With
  // `removed`, the solids the engagement reads are appended to it: what the cut took (the
  // removal volume W ∩ SV, from the same intersection; its volume checked against the stock's
  // change), or, where no attempt gives a removal volume that holds what the stock lost, a copy
  // of the stock before the cut (counted by removal_volumes_replaced()). At the points the
  // engagement tests, just outside the cutter where it moves into the material and so inside the
  // swept volume, the two are the same, but within √(2·2e-7/ρ) of a line the move grazes.
  double cut_linear(const Cutter& cutter, const Vec3& start, const Vec3& end, const Vec3& axis,
                    std::vector<Solid>* removed = nullptr);
  // The same for a planar arc with the tool along its normal (planar_arc_sweep_solids), for a
  // helix (helix_sweep_solids) and for a tilt in place (tilt_sweep_solids), their solids cut one
  // after the other.
  double cut_planar_arc(const Cutter& cutter, const Move& arc,
                        std::vector<Solid>* removed = nullptr);
  double cut_helix(const Cutter& cutter, const Move& helix, std::vector<Solid>* removed = nullptr);
  double cut_tilt(const Cutter& cutter, const Move& tilt, std::vector<Solid>* removed = nullptr);
  // The same for lines one after the other, all or none (a move the caller cut into linear
  // pieces: a simultaneous 5-axis move, each piece with one axis).
  struct Line {
    Vec3 start, end, axis;
  };
  double cut_lines(const Cutter& cutter, const std::vector<Line>& lines,
                   std::vector<Solid>* removed = nullptr);
  // The same for a line whose axis turns (a simultaneous 5-axis move), lofted through its
  // poses (lofted_sweep_solid) within `tolerance` inside the stock's box. Throws
  // ComputationError when the loft is refused or its cut fails; the stock is then unchanged.
  double cut_lofted(const Cutter& cutter, const Move& move, double tolerance,
                    std::vector<Solid>* removed = nullptr);
  // How many cut_lofted calls took, and the largest deviation measured on their lofts, mm.
  int moves_lofted() const { return moves_lofted_; }
  double worst_loft_deviation() const { return worst_loft_deviation_; }
  // How many cut_lines calls (moves cut as linear pieces, within their sweep tolerance) took.
  int moves_in_lines() const { return moves_in_lines_; }
  // Cuts whose removal volume (for the engagement) came out more than 1e-4, at most 1 %, off
  // what the stock lost, and the largest such difference relative to the loss.
  int removal_volumes_off() const { return removal_volumes_off_; }
  double worst_removal_volume() const { return worst_removal_volume_; }
  // Cuts whose removal volume no attempt could give within 1 % of what the stock lost, for
  // which `removed` holds the stock before the cut instead.
  int removal_volumes_replaced() const { return removal_volumes_replaced_; }
  // Cuts that went wrong with every fuzzy value (the stock grew, or a solid of the result lay
  // inside the swept volume) and were cut again from the stock mended by ShapeFix_Shape
  // (BrepStock::cut).
  int cuts_from_mended_stock() const { return cuts_from_mended_stock_; }
  // For the tests that hold the fallback to the removal volume: with `on`, every removal volume
  // is refused, so each cut with `removed` is tried with every fuzzy value and then takes the
  // fallback (removed gets the stock before the cut, counted above).
  void refuse_removal_volumes(bool on) { refuse_removal_volumes_ = on; }

  // Cuts a solid (a swept volume) and returns the volume removed, mm³, with the checks above.
  double cut(const Solid& cutter, std::vector<Solid>* removed = nullptr);

  double volume() const { return volume_; }  // mm³, exact (BRepGProp)
  Aabb bounds() const;
  // The box of the faces' geometry (BRepBndLib::AddOptimal): bounds() is that of their control
  // points, which grows round a loft's B-spline faces once the stock holds them.
  Aabb tight_bounds() const;
  int faces() const { return faces_; }

  const Solid& solid() const { return *solid_; }
  explicit BrepStock(std::unique_ptr<Solid> solid);

 private:
  // Cuts the solids one after the other, all or none.
  double cut_all(const std::vector<Solid>& parts, std::vector<Solid>* removed,
                 bool merge_faces = true);
  // cut(), merging the result's same-domain faces where that keeps the solid if merge_faces.
  double cut(const Solid& cutter, std::vector<Solid>* removed, bool merge_faces);
  // Freed by the module that made it (the deleter), so that a stock made in the OpenCASCADE
  // module can be moved and destroyed outside it.
  std::unique_ptr<Solid, void (*)(Solid*)> solid_;
  double volume_ = 0.0;
  int faces_ = 0;
  int moves_in_lines_ = 0;
  int moves_lofted_ = 0;
  double worst_loft_deviation_ = 0.0;
  int removal_volumes_off_ = 0;
  int removal_volumes_replaced_ = 0;
  int cuts_from_mended_stock_ = 0;
  bool refuse_removal_volumes_ = false;
  double worst_removal_volume_ = 0.0;
};

}  // namespace cwe
