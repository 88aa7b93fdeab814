// The G-code interpreter (gcode_interpreter.hpp): straight moves, arcs, splines,
// spindle-synchronised moves and canned cycles, and the moves they emit.

#include "gcode_interpreter.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"
#include "gcode_tolerance.hpp"

namespace cwe::gcode {

Vec3 Interpreter::find_end(const Block& block) const {
  if (block.g[kGroupNonModal] == kG53) {
    // Machine coordinates for this line's move (offsets suspended), absolute.
    Vec3 end = position_;
    for (int axis = 0; axis < 3; ++axis) {
      const Word& w = block[static_cast<char>('x' + axis)];
      if (w.present) end[axis] = w.value - origin_offset_[axis] - axis_offset_[axis];
    }
    return end;
  }
  // Under cutter compensation the programmed point, not the tool's, is where the plane's
  // missing and incremental coordinates come from.
  Vec3 from = position_;
  if (compensation_.uses_programmed_point()) {
    const PlaneAxes a = plane_axes(plane_);
    const Vec3 programmed = from_plane(compensation_.programmed());
    from[a.first] = programmed[a.first];
    from[a.second] = programmed[a.second];
  }
  Vec3 end = from;
  for (int axis = 0; axis < 3; ++axis) {
    const Word& w = block[static_cast<char>('x' + axis)];
    if (!w.present) continue;
    end[axis] = incremental_ ? from[axis] + w.value : w.value;
  }
  if (block.has_polar()) end.head<2>() = polar_end(block, from);
  return end;
}

// LinuxCNC's find_ends for @ and ^: absolute, the radius and angle given (the current ones for
// a missing word); incremental, added to the current ones.
Vec2 Interpreter::polar_end(const Block& block, const Vec3& from) const {
  const double x = from.x(), y = from.y();
  const Word& r = block.polar_radius;
  const Word& a = block.polar_angle;
  const int column = r.present ? r.column : a.column;
  const double degree = kPi / 180.0;
  if (!incremental_) {
    if (r.present && a.present)
      return {r.value * std::cos(a.value * degree), r.value * std::sin(a.value * degree)};
    if (r.present) {
      if (x == 0.0 && y == 0.0)
        fail(column, "must specify angle in polar coordinate if at the origin");
      const double theta = std::atan2(y, x);
      return {r.value * std::cos(theta), r.value * std::sin(theta)};
    }
    const double radius = std::hypot(y, x);
    return {radius * std::cos(a.value * degree), radius * std::sin(a.value * degree)};
  }
  if (x == 0.0 && y == 0.0) {
    fail(column, "incremental motion with polar coordinates is indeterminate when at the origin");
  }
  double radius = std::hypot(y, x), theta = std::atan2(y, x);
  if (r.present) radius += r.value;
  if (a.present) theta += a.value * degree;
  return {radius * std::cos(theta), radius * std::sin(theta)};
}

Move Interpreter::new_move(MotionMode mode) const {
  Move move;
  move.mode = mode;
  move.start = tip_;
  move.feed_rate = mode == MotionMode::kFeed ? feed_mm_per_min_ : 0.0;
  move.spindle_speed = spindle_speed_;
  move.spindle = spindle_;
  move.tool = loaded_tool_;
  move.line = line_;
  move.source = at_.file;
  return move;
}

// Zero-length moves are emitted as LinuxCNC emits them (a G1 without axis words, the repeated
// traverses of canned cycles); samplers skip them.
void Interpreter::push(const Move& move) {
  check_travel(move);
  if (sink_ != nullptr) {
    (*sink_)(move, result_.sources);
  } else {
    hold_move(result_.moves, move, SourceLocation{source_, line_});
  }
  tip_ = move.end;
  idle_iterations_ = 0;
}

// A move beyond the machine's travel (with a margin of tol::kLength) is an error at its line.
void Interpreter::check_travel(const Move& move) const {
  if (!options_.machine || !options_.machine->travel) return;
  const Aabb& travel = *options_.machine->travel;
  Aabb box = move.bounds();
  box.min += frame_offset_;
  box.max += frame_offset_;
  for (int a = 0; a < 3; ++a) {
    const char axis = static_cast<char>('X' + a);
    const bool above = box.max[a] > travel.max[a] + tol::kLength;
    if (above || box.min[a] < travel.min[a] - tol::kLength) {
      // At the move's own line (a compensated move is made when the next line is read).
      throw InputError(
          SourceLocation{result_.sources[static_cast<std::size_t>(move.source)], move.line, 0},
          fmt::format("the move goes beyond the machine's travel: {} {:.3f} mm, its limit {:.3f} "
                      "mm (machine coordinates)",
                      axis, above ? box.max[a] : box.min[a],
                      above ? travel.max[a] : travel.min[a]));
    }
  }
}

void Interpreter::emit_line(MotionMode mode, const Vec3& to) {
  Move move = new_move(mode);
  move.shape = MoveShape::kLine;
  move.end = machine(to);
  push(move);
  position_ = to;
}

void Interpreter::emit_compensated(const gcode::CompensatedMove& m) {
  Move move = m.attributes;
  move.start = tip_;
  if (m.kind == gcode::CompensatedMove::Kind::kArc) {
    emit_arc(from_plane(m.start), from_plane(m.end), m.center, m.turn, true, 0, move);
    return;
  }
  move.shape = MoveShape::kLine;
  if (m.kind == gcode::CompensatedMove::Kind::kTraverse) {
    move.mode = MotionMode::kRapid;
    move.feed_rate = 0.0;
  }
  move.end = machine(from_plane(m.end));
  push(move);
}

void Interpreter::straight(const Block& block, int motion, int column) {
  const bool g53 = block.g[kGroupNonModal] == kG53;
  if (g53) {
    if (incremental_) fail(block.g_column[kGroupNonModal], "cannot use G53 incremental");
    warn_machine("G53 (machine coordinates)");
  }
  if (motion == kG1 && feed_mm_per_min_ == 0.0) {
    fail(column, "cannot do G1 with zero feed rate");
  }
  motion_mode_ = motion;
  const Vec3 end = find_end(block);
  if (!compensation_.offsetting()) {
    compensation_.straight_move_made();
    emit_line(motion == kG0 ? MotionMode::kRapid : MotionMode::kFeed, end);
    return;
  }
  if (g53) fail(block.g_column[kGroupNonModal], "cannot use G53 with cutter radius comp");
  position_ = from_plane(compensating(column, [&] {
    return compensation_.straight(motion == kG0, to_plane(position_), to_plane(end),
                                  new_move(MotionMode::kFeed));
  }));
}

// G33 and G33.1 (LinuxCNC's convert_straight): motion at K program units per spindle
// revolution, a straight feed at K·S per minute. G33.1 taps: to the end and back to the start
// (LinuxCNC's RIGID_TAP), the spindle reversed on the way back, I times faster (I ≥ 1).
void Interpreter::synchronised(const Block& block, int motion, int column) {
  const char* name = motion == kG33 ? "G33" : "G33.1";
  if (spindle_ == SpindleDirection::kStopped) {
    fail(column, fmt::format("spindle not turning in {}", name));
  }
  // LinuxCNC has no compensated G33 (with a radius, its "BUG: code not G0 or G1").
  if (compensation_.offsetting()) {
    fail(column, "cannot use G33 or G33.1 with cutter radius compensation on");
  }
  motion_mode_ = motion;
  compensation_.straight_move_made();
  const Vec3 start = position_;
  const Vec3 end = find_end(block);
  const double feed = block['k'].value * scale() * spindle_speed_;
  Move move = new_move(MotionMode::kFeed);
  move.feed_rate = feed;
  move.end = machine(end);
  push(move);
  position_ = end;
  if (motion != kG33_1) return;
  Move back = new_move(MotionMode::kFeed);
  back.feed_rate = feed * std::max(1.0, block.has('i') ? block['i'].value : 1.0);
  back.spindle = spindle_ == SpindleDirection::kClockwise ? SpindleDirection::kCounterClockwise
                                                          : SpindleDirection::kClockwise;
  back.end = machine(start);
  push(back);
  position_ = start;
}

// G5 (cubic) and G5.1 (quadratic) B-splines in the XY plane (LinuxCNC's convert_spline). The
// curve is the Bézier polygon of its control points; it is cut in straight feed moves through
// the points LinuxCNC's own interpreter gives its previews (gcodemodule.cc NURBS_FEED): 15 per
// control point, at equal steps of the curve parameter, the step added up as LinuxCNC adds it
// so that the moves are the same in number.
void Interpreter::spline(const Block& block, int motion, int column) {
  refuse_with_compensation(true, column, "cannot convert spline with cutter radius compensation");
  if (feed_mm_per_min_ == 0.0) fail(column, "cannot make arc with zero feed rate");
  if (plane_ != Plane::kXY) fail(column, "splines must be in the XY plane");
  if (block.has('z')) fail(block['z'].column, "splines may not have motion in Z, A, B, or C");
  motion_mode_ = motion;
  const Vec2 start = position_.head<2>();
  std::vector<Vec2> points{start};
  if (motion == kG5_1) {
    if (!block.has('i') || !block.has('j')) fail(column, "must specify both I and J with G5.1");
    points.push_back(start + Vec2(block['i'].value, block['j'].value));
    points.push_back(find_end(block).head<2>());
  } else {
    if (block.has('i') != block.has('j')) fail(column, "must specify both I and J, or neither");
    const Vec2 first = block.has('i') ? Vec2(block['i'].value, block['j'].value) : spline_ij_;
    const Vec2 end = find_end(block).head<2>();
    if (!block.has('p') || !block.has('q')) fail(column, "must specify both P and Q with G5");
    const Vec2 last(block['p'].value, block['q'].value);
    points.push_back(start + first);
    points.push_back(end + last);
    points.push_back(end);
    spline_ij_ = -last;  // the next G5 without I, J continues the curve smoothly
  }
  // The Bézier point at u ∈ [0, 1] (de Casteljau).
  const auto at = [&](double u) {
    std::vector<Vec2> p = points;
    for (std::size_t level = p.size() - 1; level > 0; --level) {
      for (std::size_t i = 0; i < level; ++i) p[i] = (1.0 - u) * p[i] + u * p[i + 1];
    }
    return p[0];
  };
  const double umax = 1.0;
  const unsigned divisions = static_cast<unsigned>(points.size()) * 15u;
  const double step = umax / divisions;
  const double z = position_.z();
  for (double u = 0.0; u + step < umax; u += step) {
    const Vec2 p = at(u + step);
    emit_line(MotionMode::kFeed, Vec3(p.x(), p.y(), z));
  }
  emit_line(MotionMode::kFeed, Vec3(points.back().x(), points.back().y(), z));
}

// LinuxCNC's convert_arc and convert_arc2, or convert_arc_comp1/2 under cutter compensation.
void Interpreter::arc(const Block& block, int motion, int column) {
  if (!compensation_.arc_allowed()) {
    fail(column,
         "the move just after exiting cutter compensation mode must be straight, not an arc");
  }
  const bool ijk = block.has('i') || block.has('j') || block.has('k');
  const bool r_format = block.has('r');
  if (!r_format && !ijk) fail(column, "R, I, J and K words all missing for arc");
  if (r_format && ijk) fail(column, "mixed radius and IJK format for arc");
  if (feed_mm_per_min_ == 0.0) fail(column, "cannot make arc with zero feed rate");

  const PlaneAxes axes = plane_axes(plane_);
  const auto upper = [](char c) { return static_cast<char>(c - 'a' + 'A'); };
  if (ijk) {
    if (block.has(axes.forbidden_offset)) {
      const Word& w = block[axes.forbidden_offset];
      const std::string what = fmt::format("{} word given for arc in {} plane",
                                           upper(axes.forbidden_offset), plane_name(plane_));
      if (w.value != 0.0) fail(w.column, what);
      // grbl posts write K0 on every XY arc (grbl ignores it; LinuxCNC refuses it): a zero
      // offset along the plane's normal changes nothing, so it is read with one warning.
      if (first_warning("zero normal offset")) {
        warn(line_, w.column,
             fmt::format("{} of 0: ignored, as grbl does (LinuxCNC refuses it); later ones say "
                         "nothing",
                         what));
      }
    }
    for (char c : {axes.first_offset, axes.second_offset}) {
      if (!block.has(c) && arc_absolute_) {
        fail(column, fmt::format("{} word missing in absolute center arc (G90.1)", upper(c)));
      }
    }
  } else {
    const auto in_plane = [&](int axis) { return block.has(static_cast<char>('x' + axis)); };
    if (!in_plane(axes.first) && !in_plane(axes.second) && !block.has_polar()) {
      // LinuxCNC names the axes in alphabetical order here.
      const char low = std::min(axes.first_letter, axes.second_letter);
      const char high = std::max(axes.first_letter, axes.second_letter);
      fail(column, fmt::format("{} and {} words missing for arc in {} plane", low, high,
                               plane_name(plane_)));
    }
  }
  const int turns =
      block.has('p') ? static_cast<int>(std::round(block['p'].value)) : 1;  // checked ≥ 1

  const Vec3 end = find_end(block);
  motion_mode_ = motion;
  const Vec2 e(end[axes.first], end[axes.second]);
  if (compensation_.offsetting()) {
    gcode::ProgrammedArc programmed;
    programmed.counter_clockwise = motion == kG3;
    programmed.turns = turns;
    programmed.r_format = r_format;
    programmed.r = r_format ? block['r'].value : 0.0;
    programmed.center = [&](const Vec2& start) {
      return arc_center(block, motion, column, start, e);
    };
    position_ = from_plane(compensating(column, [&] {
      return compensation_.arc(programmed, to_plane(position_), to_plane(end),
                               new_move(MotionMode::kFeed));
    }));
    return;
  }
  const Vec2 s(position_[axes.first], position_[axes.second]);
  const Vec2 center = arc_center(block, motion, column, s, e);
  emit_arc(position_, end, center, motion == kG3 ? turns : -turns, ijk, column,
           new_move(MotionMode::kFeed));
  position_ = end;
}

// LinuxCNC's arc_data_r and arc_data_ijk (interp_arc.cc): the centre of the block's arc from
// `start` to `end`, in the plane's (first, second) coordinates.
Vec2 Interpreter::arc_center(const Block& block, int motion, int column, const Vec2& start,
                             const Vec2& end) const {
  const PlaneAxes axes = plane_axes(plane_);
  const double s1 = start.x(), s2 = start.y(), e1 = end.x(), e2 = end.y();
  const double radius_tolerance = inches_ ? tol::kGcodeArcRadiusInch : tol::kGcodeArcRadiusMm;
  const double spiral_tolerance = inches_ ? tol::kGcodeArcSpiralInch : tol::kGcodeArcSpiralMm;
  if (block.has('r')) {
    // The centre on the perpendicular bisector of the chord, on the side given by the sign of R
    // (negative: more than half a circle).
    const double radius = block['r'].value;
    if (e1 == s1 && e2 == s2) fail(column, "current point same as end point of arc (R format)");
    const double abs_radius = std::abs(radius);
    const double mid1 = (e1 + s1) / 2.0, mid2 = (e2 + s2) / 2.0;
    double half_length = std::hypot(mid1 - e1, mid2 - e2);
    if (half_length - abs_radius > radius_tolerance || abs_radius < radius_tolerance) {
      fail(block['r'].column, fmt::format("arc radius too small to reach end point: R{} for a "
                                          "chord of {:.4f}",
                                          radius, 2.0 * half_length));
    }
    if (half_length / abs_radius > 1.0 - tol::kGcodeSemicircleRelative) {
      half_length = abs_radius;  // a semicircle, within rounding
    }
    const double chord_angle = std::atan2(e2 - s2, e1 - s1);
    const bool right = (motion == kG2 && radius > 0.0) || (motion == kG3 && radius < 0.0);
    // LinuxCNC adds its long double M_PI_2l: the sum is rounded once, to double.
    const double theta =
        static_cast<double>(right ? chord_angle - kHalfPiL : chord_angle + kHalfPiL);
    const double offset = abs_radius * std::cos(std::asin(half_length / abs_radius));
    return {mid1 + offset * std::cos(theta), mid2 + offset * std::sin(theta)};
  }
  const double offset1 = block[axes.first_offset].value;
  const double offset2 = block[axes.second_offset].value;
  const double c1 = arc_absolute_ ? offset1 : s1 + offset1;
  const double c2 = arc_absolute_ ? offset2 : s2 + offset2;
  const double r1 = std::hypot(c1 - s1, c2 - s2);
  const double r2 = std::hypot(c1 - e1, c2 - e2);
  const char a = axes.first_letter, b = axes.second_letter;
  const std::string where = fmt::format(
      "start=({}{:.4f},{}{:.4f}) center=({}{:.4f},{}{:.4f}) end=({}{:.4f},{}{:.4f}) "
      "r1={:.4f} r2={:.4f}",
      a, s1, b, s2, a, c1, b, c2, a, e1, b, e2, r1, r2);
  if (r1 < radius_tolerance || r2 < radius_tolerance) fail(column, "zero-radius arc: " + where);
  const double abs_err = std::abs(r1 - r2);
  const double rel_err = abs_err / std::max(r1, r2);
  if (abs_err > 100.0 * spiral_tolerance ||
      (rel_err > tol::kGcodeArcSpiralRelative && abs_err > spiral_tolerance)) {
    fail(column, fmt::format("radius to end of arc differs from radius to start: {} "
                             "abs_err={:.4g} rel_err={:.4f}%",
                             where, abs_err, rel_err * 100.0));
  }
  return {c1, c2};
}

// An arc from `start` to `end` (program units) about `center` in the plane, `turn` as
// LinuxCNC's ARC_FEED (+n counter-clockwise about the plane's normal, -n clockwise, |n| - 1 extra
// turns). `move` carries the feed, spindle, tool and line. With `may_close`, an arc whose end is
// at its start (within tol::kLength) is a full circle.
//
// The arc must end exactly at `end`, though the radii r1 to the start and r2 to the end may
// differ (LinuxCNC's planner cuts a spiral between them):
//  - the centre moves onto the perpendicular bisector of the chord (the circle through start and
//    end nearest the programmed centre) when that moves it by no more than the spiral tolerance
//    (LinuxCNC's own bound for "the same radius") or than |r1 - r2|, so that the path stays as
//    close to LinuxCNC's spiral as the data allow; for CAM data rounded to a few decimals it
//    moves by about |r1 - r2| * radius / chord;
//  - otherwise (a short chord, typically a nearly full circle with rounded data, where every
//    circle through start and end is far from the programmed one) the arc keeps its centre and
//    start radius and ends in the direction of the programmed end, and a straight feed move of
//    length |r1 - r2| joins it to the programmed end, with a warning.
void Interpreter::emit_arc(const Vec3& start, const Vec3& end, const Vec2& center, int turn,
                           bool may_close, int column, Move move) {
  const Move attributes = move;
  const PlaneAxes axes = plane_axes(plane_);
  const double spiral_tolerance = inches_ ? tol::kGcodeArcSpiralInch : tol::kGcodeArcSpiralMm;
  const double s1 = start[axes.first], s2 = start[axes.second];
  const double e1 = end[axes.first], e2 = end[axes.second];
  double c1 = center.x(), c2 = center.y();
  const double chord = std::hypot(e1 - s1, e2 - s2);
  const bool full_circle = may_close && chord * scale() <= tol::kLength;
  bool connector = false;
  if (!full_circle) {
    const double d1 = (e1 - s1) / chord, d2 = (e2 - s2) / chord;
    const double along = (c1 - (s1 + e1) / 2.0) * d1 + (c2 - (s2 + e2) / 2.0) * d2;
    const double mismatch = std::abs(std::hypot(c1 - s1, c2 - s2) - std::hypot(c1 - e1, c2 - e2));
    if (std::abs(along) <= std::max(spiral_tolerance, mismatch)) {
      c1 -= along * d1;
      c2 -= along * d2;
    } else {
      connector = true;
    }
  }
  const double sign = turn > 0 ? 1.0 : -1.0;  // rotation about +normal axis
  const double u1 = s1 - c1, u2 = s2 - c2, v1 = e1 - c1, v2 = e2 - c2;
  double angle = std::atan2(sign * (u1 * v2 - u2 * v1), u1 * v1 + u2 * v2);
  if (full_circle) {
    angle = kTwoPi;
  } else if (angle <= 0.0) {
    angle += kTwoPi;  // the travel direction goes the long way round
  }
  Vec3 arc_end = end;
  if (connector) {
    const double r1 = std::hypot(u1, u2), r2 = std::hypot(v1, v2);  // both > 0, checked above
    arc_end[axes.first] = c1 + v1 * (r1 / r2);
    arc_end[axes.second] = c2 + v2 * (r1 / r2);
    warn(line_, column,
         fmt::format("the radii to start and end of the arc differ by {:.4g} mm and its chord is "
                     "too short for a circle through both ends near the programmed centre: the arc "
                     "keeps its centre and start radius, and a straight feed move of {:.4g} mm "
                     "joins it to the programmed end",
                     std::abs(r1 - r2) * scale(), std::abs(r1 - r2) * scale()));
  }
  move.shape = MoveShape::kArc;
  move.mode = MotionMode::kFeed;
  move.end = machine(arc_end);
  Vec3 centre = start;
  centre[axes.first] = c1;
  centre[axes.second] = c2;
  move.center = machine(centre);
  move.normal = Vec3::Zero();
  move.normal[axes.normal] = sign;
  move.sweep = angle + kTwoPi * (std::abs(turn) - 1);
  move.axial = sign * (end[axes.normal] - start[axes.normal]) * scale();
  push(move);
  if (connector) {
    Move line = attributes;
    line.shape = MoveShape::kLine;
    line.start = tip_;
    line.end = machine(end);
    push(line);
  }
}

// LinuxCNC's convert_cycle and convert_cycle_xy with CYCLE_MACRO, for G73, G81, G82 and G83 in
// the XY plane.
void Interpreter::cycle(const Block& block, int motion, int column) {
  refuse_with_compensation(true, column, "cannot use canned cycles with cutter compensation on");
  if (feed_mm_per_min_ == 0.0) fail(column, "cannot feed with zero feed rate (canned cycle)");
  if (plane_ != Plane::kXY) {
    fail(column, fmt::format("{}: canned cycles in the {} plane are not supported (only G17)",
                             g_name(motion), plane_name(plane_)));
  }
  const bool same_cycle = motion_mode_ == motion;
  double r_number = block['r'].value;
  if (!block.has('r')) {
    if (!same_cycle) fail(column, "R clearance plane unspecified in canned cycle");
    r_number = cycle_r_;
  }
  int repeats = 1;
  if (block.has('l')) {
    repeats = static_cast<int>(block['l'].value);
    if (repeats == 0) fail(block['l'].column, "cannot do zero repeats of cycle (L0)");
  }
  if (!same_cycle && !block.has('z')) {
    fail(column, "Z value unspecified in XY plane canned cycle");
  }
  const double z_number = block.has('z') ? block['z'].value : cycle_cc_;

  double current_cc = position_.z();
  double old_cc = current_cc;
  if (cycle_initial_level_set_) {
    old_cc = cycle_initial_level_;
  } else {
    cycle_initial_level_ = current_cc;
    cycle_initial_level_set_ = true;
  }
  double aa = position_.x(), bb = position_.y(), aa_increment = 0.0, bb_increment = 0.0;
  double radius_increment = 0.0, theta_increment = 0.0;  // polar repeats (LinuxCNC's CYCLE_MACRO)
  double r = r_number, cc = z_number;
  if (incremental_) {
    // X, Y and R are increments from the current point (R from the initial level), Z from R.
    aa_increment = block['x'].value;
    bb_increment = block['y'].value;
    if (block.polar_radius.present) radius_increment = block.polar_radius.value;
    if (block.polar_angle.present) theta_increment = block.polar_angle.value * kPi / 180.0;
    r = r_number + old_cc;
    cc = r + z_number;
  } else if (block.has_polar()) {
    const double radius =
        block.polar_radius.present ? block.polar_radius.value : std::hypot(bb, aa);
    const double theta =
        block.polar_angle.present ? block.polar_angle.value * kPi / 180.0 : std::atan2(bb, aa);
    aa = radius * std::cos(theta);
    bb = radius * std::sin(theta);
  } else {
    if (block.has('x')) aa = block['x'].value;
    if (block.has('y')) bb = block['y'].value;
  }
  if (r < cc) {
    fail(block.has('r') ? block['r'].column : column,
         "R less than Z in canned cycle (the clearance plane is below the bottom)");
  }

  double dwell = 0.0, delta = 0.0;
  if (motion == kG82) {
    if (!same_cycle && !block.has('p')) fail(column, "dwell time P word missing with G82");
    dwell = block.has('p') ? block['p'].value : cycle_p_;
    if (dwell < 0.0) fail(block['p'].column, "negative dwell time (P word) with G82");
  } else if (motion == kG73 || motion == kG83) {
    if (!same_cycle && !block.has('q')) {
      fail(column, fmt::format("Q word missing with {}", g_name(motion)));
    }
    delta = block.has('q') ? block['q'].value : cycle_q_;
    if (delta <= 0.0) {
      fail(block.has('q') ? block['q'].column : column, "negative or zero Q value used");
    }
  }
  const double pecks = delta > 0.0 ? std::ceil((r - cc) / delta) : 0.0;
  if (repeats * (pecks + 1.0) * 3.0 > kMaxCycleMoves) {
    fail(column, fmt::format("{} would expand to more than {:g} moves (L{}, {:g} pecks)",
                             g_name(motion), kMaxCycleMoves, repeats, pecks));
  }
  const double rapid_delta =
      inches_ ? kPeckClearanceInch : kPeckClearanceInch * kMillimetresPerInch;

  // First motion, maybe: from below the R plane, rapid straight up to it.
  if (old_cc < r) {
    cycle_traverse(position_.x(), position_.y(), r);
    old_cc = r;
    current_cc = old_cc;
  }
  const double clear_cc = retract_to_r_ ? r : old_cc;

  for (int repeat = repeats; repeat > 0; --repeat) {
    aa += aa_increment;
    bb += bb_increment;
    // The radius, then the angle, stepped in turn, as LinuxCNC does.
    const auto step = [&](double d_radius, double d_theta) {
      if (aa == 0.0 && bb == 0.0) {
        fail(column,
             "incremental motion with polar coordinates is indeterminate when at the origin");
      }
      const double radius = std::hypot(bb, aa) + d_radius, theta = std::atan2(bb, aa) + d_theta;
      aa = radius * std::cos(theta);
      bb = radius * std::sin(theta);
    };
    if (radius_increment != 0.0) step(radius_increment, 0.0);
    if (theta_increment != 0.0) step(0.0, theta_increment);
    // The first positioning move happens at the current height (raised to R above), later
    // ones at the clearance height.
    if (repeat == repeats && current_cc > r) {
      cycle_traverse(aa, bb, current_cc);
      cycle_traverse(aa, bb, r);
    } else {
      cycle_traverse(aa, bb, clear_cc);
      if (clear_cc > r) cycle_traverse(aa, bb, r);
    }
    switch (motion) {
      case kG73:  // chip breaking: feed a peck, rapid back up a little
        for (double depth = r - delta; depth > cc; depth -= delta) {
          cycle_feed(aa, bb, depth);
          cycle_traverse(aa, bb, depth + rapid_delta);
        }
        break;
      case kG83:  // peck: feed a peck, rapid out to R, rapid back to just above the depth
        for (double depth = r - delta; depth > cc; depth -= delta) {
          cycle_feed(aa, bb, depth);
          cycle_traverse(aa, bb, r);
          cycle_traverse(aa, bb, depth + rapid_delta);
        }
        break;
      default:  // G81, G82 (the dwell does not move)
        break;
    }
    cycle_feed(aa, bb, cc);
    cycle_traverse(aa, bb, clear_cc);
  }
  cycle_cc_ = z_number;
  cycle_r_ = r_number;
  if (motion == kG82) cycle_p_ = dwell;
  if (motion == kG73 || motion == kG83) cycle_q_ = delta;
  motion_mode_ = motion;
}

}  // namespace cwe::gcode
