#include "gcode_compensation.hpp"

#include <cmath>

#include <fmt/format.h>

#include "gcode_tolerance.hpp"

// A line-by-line rendering of LinuxCNC 2.9's cutter compensation (interp_convert.cc,
// interp_queue.cc), so that cwe's compensated moves are LinuxCNC's to the last bit: the variable
// names are LinuxCNC's, lengths are hypot's as there, and where LinuxCNC adds its long double
// M_PIl or M_PI_2l the sum is formed in long double too (kPiL, kHalfPiL) and rounded once.

namespace cwe::gcode {
namespace {

constexpr double kHalfPi = kPi / 2.0;  // LinuxCNC's gamma: M_PI_2l stored in a double

// LinuxCNC's hypot of a difference.
double distance(const Vec2& a, const Vec2& b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

// A long double sum rounded to double, as LinuxCNC assigns it.
double rounded(long double value) { return static_cast<double>(value); }

bool tool_inside_arc(CompensationSide side, int turn) {
  return (side == CompensationSide::kLeft && turn > 0) ||
         (side == CompensationSide::kRight && turn < 0);
}

double direction(const Vec2& from, const Vec2& to) {
  return std::atan2(to.y() - from.y(), to.x() - from.x());
}

Vec2 polar(const Vec2& origin, double radius, double angle) {
  return {origin.x() + radius * std::cos(angle), origin.y() + radius * std::sin(angle)};
}

[[noreturn]] void refuse(const std::string& message) { throw CompensationError(message); }

}  // namespace

double find_turn(const Vec2& from, const Vec2& center, int turn, const Vec2& to) {
  if (turn == 0) return 0.0;
  double alpha = direction(center, from);
  double beta = direction(center, to);
  if (turn > 0) {
    if (beta <= alpha) beta = rounded(beta + 2 * kPiL);
    return rounded((beta - alpha) + (turn - 1) * (2 * kPiL));
  }
  if (alpha <= beta) alpha = rounded(alpha + 2 * kPiL);
  return rounded((beta - alpha) + (turn + 1) * (2 * kPiL));
}

void CutterCompensation::turn_on(CompensationSide side, double radius, bool inches) {
  if (radius < 0.0) {  // a tool smaller than the path was made for: the other side
    radius = -radius;
    side = side == CompensationSide::kLeft ? CompensationSide::kRight : CompensationSide::kLeft;
  }
  side_ = side;
  radius_ = radius;
  inches_ = inches;
}

bool CutterCompensation::turn_off(const Vec3& current) {
  bool released = false;
  if (on() && radius_ > 0.0 && !first_move_) {
    move_endpoint_and_flush(current.x(), current.y());
    dequeue();
    arc_not_allowed_ = true;
    released = true;
  }
  side_ = CompensationSide::kNone;
  first_move_ = true;
  return released;
}

void CutterCompensation::release(const Vec3& current) {
  move_endpoint_and_flush(current.x(), current.y());
  dequeue();
}

void CutterCompensation::stop(const Vec3& current) {
  release(current);
  side_ = CompensationSide::kNone;
  first_move_ = true;
}

std::size_t CutterCompensation::held() const { return queue_.size(); }

int CutterCompensation::first_held_line() const {
  return queue_.empty() ? 0 : queue_.front().move.attributes.line;
}

void CutterCompensation::scale(double factor, bool inches) {
  inches_ = inches;
  radius_ *= factor;
  programmed_ *= factor;
  emitted_ *= factor;
  endpoint_ *= factor;
  for (Held& q : queue_) {
    q.move.end *= factor;
    q.move.center *= factor;
  }
}

void CutterCompensation::dequeue() {
  endpoint_valid_ = false;
  for (Held& q : queue_) {
    q.move.start = emitted_;
    sink_(q.move);
    emitted_ = q.move.end;
  }
  queue_.clear();
}

void CutterCompensation::move_endpoint_and_flush(double x, double y) {
  if (queue_.empty()) return;
  const Vec2 to(x, y);
  for (Held& q : queue_) {
    // Several held moves (into a concave corner, then up and back down) all end there.
    CompensatedMove& m = q.move;
    if (m.kind == CompensatedMove::Kind::kArc) {
      const double r1 = distance(m.end.head<2>(), m.center);
      const double r2 = distance(to, m.center);
      const double l1 = q.original_turns;
      const double l2 = find_turn(endpoint_, m.center, m.turn, to);
      if (std::abs(r1 - r2) > tol::kGcodeCompensatedArcRadii) {
        refuse(
            fmt::format("cutter compensation has generated an invalid arc with mismatched "
                        "radii r1 {:.6f} r2 {:.6f}",
                        r1, r2));
      }
      const double gouge =
          inches_ ? tol::kGcodeCompensatedArcGougeInch : tol::kGcodeCompensatedArcGougeMm;
      if (l1 != 0.0 && endpoint_valid_ && std::abs(l2) > std::abs(l1) + gouge) {
        refuse("arc move in concave corner cannot be reached by the tool without gouging");
      }
    } else if (endpoint_valid_ && q.direction.dot(to - endpoint_) < 0.0) {
      // The path crosses itself: the corner backs up further than the move is long.
      refuse(
          fmt::format("straight {} in concave corner cannot be reached by the tool without "
                      "gouging",
                      m.kind == CompensatedMove::Kind::kTraverse ? "traverse" : "feed"));
    }
    m.end.head<2>() = to;
  }
  dequeue();
  set_endpoint(x, y);
}

CutterCompensation::Held CutterCompensation::line(bool rapid, const Vec2& direction,
                                                  const Vec3& end, const Move& attributes) const {
  Held held;
  held.move.kind = rapid ? CompensatedMove::Kind::kTraverse : CompensatedMove::Kind::kFeed;
  held.move.end = end;
  held.move.attributes = attributes;
  held.direction = direction;
  return held;
}

CutterCompensation::Held CutterCompensation::arc_move(double original_turns, const Vec3& end,
                                                      const Vec2& center, int turn,
                                                      const Move& attributes) const {
  Held held;
  held.move.kind = CompensatedMove::Kind::kArc;
  held.move.end = end;
  held.move.center = center;
  held.move.turn = turn;
  held.move.attributes = attributes;
  held.original_turns = original_turns;
  return held;
}

const CutterCompensation::Held* CutterCompensation::front_arc() const {
  if (queue_.empty() || queue_.front().move.kind != CompensatedMove::Kind::kArc) return nullptr;
  return &queue_.front();
}

Vec3 CutterCompensation::straight(bool rapid, const Vec3& current, const Vec3& end,
                                  const Move& attributes) {
  arc_not_allowed_ = false;
  return first_move_ ? straight_first(rapid, current, end, attributes)
                     : straight_next(rapid, current, end, attributes);
}

Vec3 CutterCompensation::arc(const ProgrammedArc& arc, const Vec3& current, const Vec3& end,
                             const Move& attributes) {
  if (arc_not_allowed_) {
    refuse("the move just after exiting cutter compensation mode must be straight, not an arc");
  }
  return first_move_ ? arc_first(arc, current, end, attributes)
                     : arc_next(arc, current, end, attributes);
}

// convert_straight_comp1: the entry move ends one radius beside the programmed end, square to
// the move.
Vec3 CutterCompensation::straight_first(bool rapid, const Vec3& current, const Vec3& end,
                                        const Move& attributes) {
  const Vec2 c = current.head<2>(), p = end.head<2>();
  if (distance(p, c) <= radius_) {
    refuse("length of cutter compensation entry move is not greater than the tool radius");
  }
  const double alpha =
      rounded(direction(c, p) + (side_ == CompensationSide::kLeft ? kHalfPiL : -kHalfPiL));
  const Vec2 tool = polar(p, radius_, alpha);
  set_endpoint(c.x(), c.y());
  emitted_ = current;
  enqueue(line(rapid, Vec2(std::cos(alpha), std::sin(alpha)), Vec3(tool.x(), tool.y(), end.z()),
               attributes));
  first_move_ = false;
  programmed_ = end;
  return {tool.x(), tool.y(), end.z()};
}

// convert_straight_comp2.
Vec3 CutterCompensation::straight_next(bool rapid, const Vec3& current, const Vec3& end,
                                       const Move& attributes) {
  const double cx = current.x(), cy = current.y(), cz = current.z();
  const double px = end.x(), py = end.y(), pz = end.z();
  const double opx = programmed_.x(), opy = programmed_.y();
  const Vec2 op(opx, opy);
  Vec3 tool(cx, cy, pz);
  if (py == opy && px == opx) {  // no motion in the plane: waits with the move before
    enqueue(line(rapid, Vec2::Zero(), tool, attributes));
    programmed_ = end;
    return tool;
  }
  const bool left = side_ == CompensationSide::kLeft;
  const double small = tol::kGcodeConcaveCorner;
  double theta = std::atan2(cy - opy, cx - opx);
  double alpha = std::atan2(py - opy, px - opx);
  double beta = 0.0, gamma = 0.0;
  if (left) {
    if (theta < alpha) theta = rounded(theta + 2 * kPiL);
    beta = rounded((theta - alpha) - kHalfPiL);
    gamma = kHalfPi;
  } else {
    if (alpha < theta) alpha = rounded(alpha + 2 * kPiL);
    beta = rounded((alpha - theta) - kHalfPiL);
    gamma = -kHalfPi;
  }
  const Vec2 end_xy = polar(Vec2(px, py), radius_, alpha + gamma);
  const Vec2 mid = polar(op, radius_, alpha + gamma);
  const Held* arc = front_arc();
  bool concave = false;
  if (beta < -small || beta > kPiL + small) {
    concave = true;
  } else if (beta > kPiL - small && arc != nullptr &&
             ((!left && arc->move.turn > 0) || (left && arc->move.turn < 0))) {
    // An "h" shape: over the round part, then down beside the straight one. Of the two ways
    // to stay on the side, LinuxCNC takes the one above.
    concave = true;
  }
  if (!concave && beta > small) {  // convex: round the corner
    move_endpoint_and_flush(cx, cy);
    if (!rapid) {
      enqueue(arc_move(0.0, Vec3(mid.x(), mid.y(), cz), op, left ? -1 : 1, attributes));
    } else {
      // There is no arc traverse: a traverse to where the arc would end.
      enqueue(line(true, Vec2::Zero(), Vec3(mid.x(), mid.y(), cz), attributes));
    }
    dequeue();
    set_endpoint(mid.x(), mid.y());
  } else if (concave && arc == nullptr) {  // line to line: back along the held line
    const double halfcorner = rounded((beta + kPiL) / 2.0);
    if (halfcorner == 0.0) refuse("zero degree inside corner is invalid for cutter compensation");
    const double retreat = radius_ / std::tan(halfcorner);
    const Vec2 back = polar(Vec2(cx, cy), retreat, theta + gamma);
    move_endpoint_and_flush(back.x(), back.y());
  } else if (concave) {  // arc to line: back along the held (compensated) arc
    const CompensatedMove prev = arc->move;
    const double oldrad = distance(prev.center, prev.end.head<2>());
    const double base_dir = std::atan2(py - opy, px - opx);
    const double th = rounded(prev.turn > 0 ? base_dir + kHalfPiL : base_dir - kHalfPiL);
    const double phi = direction(op, prev.center);
    const bool inside = tool_inside_arc(side_, prev.turn);
    const double oldrad_uncomp = inside ? oldrad + radius_ : oldrad - radius_;
    const double d = oldrad_uncomp * std::cos(th - phi);  // to the old centre, square to the line
    const double l = (inside ? d - radius_ : d + radius_) / oldrad;
    if (l > 1.0 || l < -1.0) {
      refuse(
          "arc to straight motion makes a corner the compensated tool can't fit in without "
          "gouging");
    }
    const bool plus = inside ? prev.turn < 0 : prev.turn > 0;
    const double angle_from_center = rounded(((plus ? std::acos(l) : -std::acos(l)) + th) + kPiL);
    const Vec2 back = polar(prev.center, oldrad, angle_from_center);
    move_endpoint_and_flush(back.x(), back.y());
  } else {  // straight on (or a tangent arc to line)
    dequeue();
    set_endpoint(cx, cy);
  }
  tool = Vec3(end_xy.x(), end_xy.y(), pz);
  enqueue(line(rapid, Vec2(px - opx, py - opy), tool, attributes));
  programmed_ = end;
  return tool;
}

// convert_arc_comp1: the tool stays tangent to an arc through the programmed end that touches it
// where it stands.
Vec3 CutterCompensation::arc_first(const ProgrammedArc& arc, const Vec3& current, const Vec3& end,
                                   const Move& attributes) {
  const Vec2 c = current.head<2>();
  Vec2 e = end.head<2>();
  if (distance(e, c) <= radius_) {
    refuse("radius of cutter compensation entry arc is not greater than the tool radius");
  }
  const int turn = arc.counter_clockwise ? arc.turns : -arc.turns;
  const bool inside = tool_inside_arc(side_, turn);
  const char* too_small = "tool radius not less than arc radius with comp";
  if (arc.r_format && std::abs(arc.r) <= radius_ && inside) refuse(too_small);
  Vec2 center = arc.center(c);
  if (!arc.r_format && distance(center, c) <= radius_ && inside) refuse(too_small);

  // The tool ends in direction gamma from the programmed end.
  const double gamma = inside ? direction(e, center) : direction(center, e);
  first_move_ = false;
  programmed_ = end;
  e = polar(e, radius_, gamma);

  // The centre of the compensated arc: on the line from its end to the programmed centre, at
  // the same distance from its start and its end.
  const double b_len = distance(c, e) / 2.0;
  const double ab_ang = direction(e, center);
  const double a_ang = direction(e, c) - ab_ang;
  if (std::abs(std::cos(a_ang)) < tol::kGcodeEqual) refuse(too_small);
  const double c_len = b_len / std::cos(a_ang);
  center = polar(e, c_len, ab_ang);
  const double spiral = inches_ ? tol::kGcodeArcSpiralInch : tol::kGcodeArcSpiralMm;
  if (std::abs(distance(center, e) - distance(center, c)) > spiral) {
    refuse("bug in tool radius comp");
  }
  emitted_ = current;
  const Vec3 tool(e.x(), e.y(), end.z());
  enqueue(arc_move(find_turn(c, center, turn, e), tool, center, turn, attributes));
  return tool;
}

// convert_arc_comp2.
Vec3 CutterCompensation::arc_next(const ProgrammedArc& arc, const Vec3& current, const Vec3& end,
                                  const Move& attributes) {
  const Vec2 op = programmed_.head<2>();
  const Vec2 c = current.head<2>();
  const Vec2 e = end.head<2>();
  const Vec2 center = arc.center(op);
  const int turn = arc.counter_clockwise ? arc.turns : -arc.turns;
  const bool left = side_ == CompensationSide::kLeft;
  const double small = tol::kGcodeConcaveCorner;

  const double arc_radius = distance(center, e);
  double theta = direction(op, c);
  theta = rounded(left ? theta - kHalfPiL : theta + kHalfPiL);  // the direction of the last cut
  double delta = direction(op, center);
  const double alpha = rounded(arc.counter_clockwise ? delta - kHalfPiL : delta + kHalfPiL);
  double beta = left ? theta - alpha : alpha - theta;
  if (beta > 1.5 * kPiL) {
    beta = rounded(beta - 2 * kPiL);
  } else if (beta < -kHalfPiL) {
    beta = rounded(beta + 2 * kPiL);
  }
  const bool inside = tool_inside_arc(side_, turn);
  double gamma = 0.0;
  if (inside) {
    gamma = direction(e, center);
    if (arc_radius <= radius_) refuse("tool radius not less than arc radius with comp");
  } else {
    gamma = direction(center, e);
    delta = rounded(delta + kPiL);
  }
  const Vec2 new_end = polar(e, radius_, gamma);
  const Vec3 tool(new_end.x(), new_end.y(), end.z());
  const auto main_arc = [&] {
    return arc_move(find_turn(op, center, turn, e), tool, center, turn, attributes);
  };

  // Concave, or the top of an "m" (tangent arc to arc) or "h" (tangent line to arc) shape.
  if (beta < -small || beta > kPiL + small || (std::abs(beta - kPiL) < small && !inside)) {
    const Held* held_arc = front_arc();
    Vec2 mid;
    if (held_arc == nullptr) {  // line to arc
      const double across = rounded(arc_radius * std::sin(beta - kHalfPiL));
      const double dist_from_center = inside ? arc_radius - radius_ : arc_radius + radius_;
      const double toward_nominal = inside ? across + radius_ : across - radius_;
      const double l = toward_nominal / dist_from_center;
      if (l > 1.0 || l < -1.0) {
        refuse("arc move in concave corner cannot be reached by the tool without gouging");
      }
      double angle_from_center = 0.0;
      if (inside) {
        angle_from_center = turn > 0 ? theta + std::asin(l) : theta - std::asin(l);
      } else {
        angle_from_center =
            rounded(turn > 0 ? (theta + kPiL) - std::asin(l) : (theta + kPiL) + std::asin(l));
      }
      mid = polar(center, dist_from_center, angle_from_center);
    } else {  // arc to arc
      const CompensatedMove& prev = held_arc->move;
      const double oldrad = distance(prev.center, prev.end.head<2>());
      const double newrad = inside ? arc_radius - radius_ : arc_radius + radius_;
      const double arc_cc = distance(prev.center, center);
      if (oldrad == 0.0 || arc_cc == 0.0) {
        refuse("arc to arc motion is invalid because the arcs have the same center");
      }
      const double a =
          (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2 * oldrad * arc_cc);
      if (a > 1.0 || a < -1.0) {
        refuse(
            "arc to arc motion makes a corner the compensated tool can't fit in without "
            "gouging");
      }
      const double pullback = std::acos(a);
      const double cc_dir = direction(prev.center, center);
      const bool plus = tool_inside_arc(side_, prev.turn) ? turn > 0 : turn < 0;
      mid = polar(prev.center, oldrad, plus ? cc_dir + pullback : cc_dir - pullback);
    }
    move_endpoint_and_flush(mid.x(), mid.y());
    enqueue(main_arc());
  } else if (beta > small) {  // convex: an arc about the programmed corner, then the arc
    const Vec2 mid = polar(op, radius_, delta);
    dequeue();
    enqueue(arc_move(0.0, Vec3(mid.x(), mid.y(), current.z()), op, left ? -1 : 1, attributes));
    dequeue();
    set_endpoint(mid.x(), mid.y());
    enqueue(main_arc());
  } else {  // tangent
    dequeue();
    set_endpoint(c.x(), c.y());
    enqueue(main_arc());
  }
  programmed_ = end;
  return tool;
}

}  // namespace cwe::gcode
