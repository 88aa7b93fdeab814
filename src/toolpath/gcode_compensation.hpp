#pragma once
// Cutter radius compensation (G41, G42, G41.1, G42.1) as LinuxCNC 2.9's interpreter computes it:
// interp_convert.cc convert_straight_comp1/2 and convert_arc_comp1/2, and the move queue of
// interp_queue.cc. Private to the G-code reader.
//
// Everything here is in the compensation plane's coordinates, in program units: a point is
// (first, second, third) = (X, Y, Z) under G17 and (Z, X, Y) under G18, as LinuxCNC's
// comp_get_current orders them. The tool runs one radius to the left (G41) or right (G42) of the
// programmed path, seen along the direction of travel. A compensated move is held back until the
// next one shows the corner between them:
//  - convex (the tool outside the corner): an arc of the tool radius about the programmed corner
//    is inserted between them (for a rapid, a straight traverse to the arc's end instead);
//  - concave (the tool inside): the held move's end is pulled back to where the tool touches
//    both, and LinuxCNC's errors apply when it cannot get there without gouging.
// A move that only changes the third axis waits with the move before it and ends where that one
// ends. G40, M0, M1, M2 and M30 release the moves still held.
//
// Where LinuxCNC's own code is accidental, cwe does the evident thing instead (docs/gcode.md):
//  - after M0/M1 the queue is empty, and LinuxCNC's next corner reads its first element anyway
//    (the storage of the move just released); cwe sees no held move there;
//  - a unit change while moves are held scales LinuxCNC's queue start once per held move; cwe
//    scales it once;
//  - lathe tool orientations (LinuxCNC's tool table Q, G41.1 L1-L8) are not modelled: cwe's tool
//    tables have none, and G41.1/G42.1 with such an L is refused.

#include <functional>
#include <stdexcept>
#include <vector>

#include "cwe/geometry/vec.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe::gcode {

// LinuxCNC's refusal of a compensated move, worded as it words it; the reader adds the place.
class CompensationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class CompensationSide { kNone, kLeft, kRight };

// A compensated move as LinuxCNC's canon receives it: STRAIGHT_TRAVERSE, STRAIGHT_FEED or
// ARC_FEED. `start` is where the previous one ended.
struct CompensatedMove {
  enum class Kind { kTraverse, kFeed, kArc };
  Kind kind = Kind::kFeed;
  Vec3 start = Vec3::Zero();
  Vec3 end = Vec3::Zero();
  Vec2 center = Vec2::Zero();  // arcs, in the plane
  int turn = 0;                // arcs: +n counter-clockwise, -n clockwise, |n| - 1 extra turns
  Move attributes;             // feed, spindle, tool and source line of the block that made it
};

// The data of a programmed arc: its direction and turns, and how its centre follows from a start
// point (the reader's R or IJK rules, with their errors).
struct ProgrammedArc {
  bool counter_clockwise = true;  // G3
  int turns = 1;                  // P
  bool r_format = false;
  double r = 0.0;  // R, when r_format
  std::function<Vec2(const Vec2& start)> center;
};

class CutterCompensation {
 public:
  using Sink = std::function<void(const CompensatedMove&)>;
  // `sink` receives each move once it is final, in order.
  explicit CutterCompensation(Sink sink) : sink_(std::move(sink)) {}

  // G41/G42/G41.1/G42.1 with the tool radius in program units; a negative radius switches the
  // side (LinuxCNC's convert_cutter_compensation_on). `inches`: the program's units (LinuxCNC's
  // gouge test for arcs allows 0.001 in or 0.0254 mm).
  void turn_on(CompensationSide side, double radius, bool inches);
  // G40: releases the held moves; returns true when the reader's current point becomes the
  // programmed one (`programmed()`), as in LinuxCNC: the next move starts from there in the
  // program's terms while the tool is where the last compensated move left it.
  bool turn_off(const Vec3& current);
  // M0, M1: releases the held moves; compensation stays on.
  void release(const Vec3& current);
  // M2, M30: releases the held moves and turns compensation off, the current point unchanged.
  void stop(const Vec3& current);

  bool on() const { return side_ != CompensationSide::kNone; }
  // Moves are offset: compensation is on with a radius above zero.
  bool offsetting() const { return on() && radius_ > 0.0; }
  // The programmed point stands for the current one in incremental moves and missing axes of
  // the compensation plane (LinuxCNC's find_ends "comp && middle").
  bool uses_programmed_point() const { return on() && !first_move_; }
  const Vec3& programmed() const { return programmed_; }
  // LinuxCNC refuses an arc as the first move after G40 released held moves.
  bool arc_allowed() const { return !arc_not_allowed_; }
  // How many moves are held back (for the end of a program that never turns compensation off).
  std::size_t held() const;
  int first_held_line() const;

  // A straight move (or arc) from the tool at `current` to the programmed `end`, offsetting();
  // returns where the tool ends. Throws CompensationError.
  Vec3 straight(bool rapid, const Vec3& current, const Vec3& end, const Move& attributes);
  Vec3 arc(const ProgrammedArc& arc, const Vec3& current, const Vec3& end, const Move& attributes);
  // After a straight move made with compensation on but no offset (radius 0), or off.
  void straight_move_made() { arc_not_allowed_ = false; }

  // G20/G21 while moves are held: everything is converted (LinuxCNC's qc_scale).
  void scale(double factor, bool inches);

 private:
  struct Held {
    CompensatedMove move;
    Vec2 direction = Vec2::Zero();  // lines: the programmed direction (the gouge test)
    double original_turns = 0.0;    // arcs: the signed sweep before any end was moved (rad)
  };
  void enqueue(const Held& held) { queue_.push_back(held); }
  void dequeue();  // emits the held moves (LinuxCNC's dequeue_canons)
  void move_endpoint_and_flush(double x, double y);
  void set_endpoint(double x, double y) {
    endpoint_ = Vec2(x, y);
    endpoint_valid_ = true;
  }
  Vec3 straight_first(bool rapid, const Vec3& current, const Vec3& end, const Move& attributes);
  Vec3 straight_next(bool rapid, const Vec3& current, const Vec3& end, const Move& attributes);
  Vec3 arc_first(const ProgrammedArc& arc, const Vec3& current, const Vec3& end,
                 const Move& attributes);
  Vec3 arc_next(const ProgrammedArc& arc, const Vec3& current, const Vec3& end,
                const Move& attributes);
  Held line(bool rapid, const Vec2& direction, const Vec3& end, const Move& attributes) const;
  Held arc_move(double original_turns, const Vec3& end, const Vec2& center, int turn,
                const Move& attributes) const;
  const Held* front_arc() const;

  Sink sink_;
  CompensationSide side_ = CompensationSide::kNone;
  double radius_ = 0.0;
  bool first_move_ = true;
  bool arc_not_allowed_ = false;
  bool inches_ = false;
  Vec3 programmed_ = Vec3::Zero();
  std::vector<Held> queue_;
  Vec3 emitted_ = Vec3::Zero();   // where the last released move ended
  Vec2 endpoint_ = Vec2::Zero();  // where the held moves start (LinuxCNC's endpoint)
  bool endpoint_valid_ = false;
};

// π and π/2 in long double, as LinuxCNC's M_PIl and M_PI_2l: it adds them to double angles, so
// its sums are rounded once, from long double, and its comparisons with them are exact.
inline constexpr long double kPiL = 3.141592653589793238462643383279502884L;
inline constexpr long double kHalfPiL = kPiL / 2;

// LinuxCNC's find_turn: the signed angle (rad) swept from (x1, y1) to (x2, y2) about `center`
// making `turn` turns (+ counter-clockwise); 0 for turn 0.
double find_turn(const Vec2& from, const Vec2& center, int turn, const Vec2& to);

}  // namespace cwe::gcode
