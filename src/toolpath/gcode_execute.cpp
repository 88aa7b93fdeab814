// The G-code interpreter (gcode_interpreter.hpp): checking and executing a block in LinuxCNC's
// order, the modal state, predefined parameters, cutter compensation on and off.

#include "gcode_interpreter.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"
#include "gcode_tolerance.hpp"

namespace cwe::gcode {

std::optional<double> Interpreter::predefined(std::string_view name) const {
  const auto flag = [](bool b) { return b ? 1.0 : 0.0; };
  const double plane = plane_ == Plane::kXY ? 170.0 : (plane_ == Plane::kXZ ? 180.0 : 190.0);
  // Name, value; LinuxCNC 2.9's list (interp_namedparams.cc), less the pockets of a tool
  // changer and the INI file's values, which a program run here does not have.
  const std::pair<std::string_view, double> table[] = {
      {"_vmajor", 2.0},
      {"_vminor", 9.0},
      {"_line", static_cast<double>(line_)},
      {"_motion_mode", static_cast<double>(motion_mode_)},
      {"_plane", plane},
      {"_ccomp", 400.0},
      {"_metric", flag(!inches_)},
      {"_imperial", flag(inches_)},
      {"_absolute", flag(!incremental_)},
      {"_incremental", flag(incremental_)},
      {"_inverse_time", 0.0},
      {"_units_per_minute", 1.0},
      {"_units_per_rev", 0.0},
      {"_coord_system", origin_index_ < 7 ? 530.0 + 10.0 * origin_index_ : 584.0 + origin_index_},
      {"_tool_offset", 0.0},
      {"_retract_r_plane", flag(retract_to_r_)},
      {"_retract_old_z", flag(!retract_to_r_)},
      {"_spindle_rpm_mode", 1.0},
      {"_spindle_css_mode", 0.0},
      {"_ijk_absolute_mode", flag(arc_absolute_)},
      {"_lathe_diameter_mode", 0.0},
      {"_lathe_radius_mode", 1.0},
      {"_spindle_on", flag(spindle_ != SpindleDirection::kStopped)},
      {"_spindle_cw", flag(spindle_ == SpindleDirection::kClockwise)},
      {"_mist", flag(mist_)},
      {"_flood", flag(flood_)},
      {"_speed_override", 1.0},
      {"_feed_override", 1.0},
      {"_adaptive_feed", 0.0},
      {"_feed_hold", 0.0},
      {"_feed", feed_mm_per_min_ / scale()},
      {"_rpm", spindle_speed_},
      {"_current_tool", static_cast<double>(loaded_tool_)},
      {"_selected_tool", static_cast<double>(selected_tool_)},
      {"_x", position_.x()},
      {"_y", position_.y()},
      {"_z", position_.z()},
      {"_a", 0.0},
      {"_b", 0.0},
      {"_c", 0.0},
      {"_u", 0.0},
      {"_v", 0.0},
      {"_w", 0.0},
      {"_abs_x", position_.x() + origin_offset_.x() + axis_offset_.x()},
      {"_abs_y", position_.y() + origin_offset_.y() + axis_offset_.y()},
      {"_abs_z", position_.z() + origin_offset_.z() + axis_offset_.z()},
      {"_abs_a", 0.0},
      {"_abs_b", 0.0},
      {"_abs_c", 0.0},
      {"_value", return_value_},
      {"_value_returned", flag(value_returned_)},
      {"_call_level", static_cast<double>(frames_.size() - 1)},
      {"_remap_level", 0.0},
      {"_task", 0.0},
  };
  for (const auto& [key, value] : table) {
    if (key == name) return value;
  }
  return std::nullopt;
}

Interpreter::ModalState Interpreter::modal_state() const {
  ModalState m;
  m.inches = inches_;
  m.feed = feed_mm_per_min_ / scale();
  m.speed = spindle_speed_;
  m.plane = plane_;
  m.incremental = incremental_;
  m.arc_absolute = arc_absolute_;
  m.retract_to_r = retract_to_r_;
  m.g92_applied = parameters_.numbered(5210) != 0.0;
  m.origin = origin_index_;
  m.compensation = compensation_code_;
  m.spindle = spindle_;
  m.mist = mist_;
  m.flood = flood_;
  return m;
}

// LinuxCNC's restore_settings: it writes the differences as G-code and runs it, units first; so
// F comes back rounded to 0.1 and S to 1 when they changed (its "F%.1f", "S%.0f").
void Interpreter::restore(const ModalState& saved) {
  set_units(saved.inches);
  if (saved.feed != feed_mm_per_min_ / scale()) {
    feed_mm_per_min_ = std::stod(fmt::format("{:.1f}", saved.feed)) * scale();
  }
  if (saved.speed != spindle_speed_) spindle_speed_ = std::stod(fmt::format("{:.0f}", saved.speed));
  // The G codes that differ run as one line, in LinuxCNC's order, with its refusals under cutter
  // compensation.
  if (saved.plane != plane_) {
    refuse_with_compensation(true, 0, "cannot change planes with cutter radius compensation on");
    plane_ = saved.plane;
  }
  if (saved.compensation != compensation_code_) {
    if (saved.compensation == kG40) {
      compensation_off(0);
    } else {
      compensation_on(Block(), saved.compensation);  // G41, G42 without D; G41.1 fails
    }
  }
  if (saved.origin != origin_index_) {
    refuse_with_compensation(true, 0,
                             "cannot change coordinate systems with cutter radius compensation on");
    select_origin(saved.origin);
  }
  incremental_ = saved.incremental;
  arc_absolute_ = saved.arc_absolute;
  if (saved.retract_to_r != retract_to_r_) {
    refuse_with_compensation(true, 0,
                             "cannot change retract mode with cutter radius compensation on");
    retract_to_r_ = saved.retract_to_r;
  }
  if (saved.g92_applied != (parameters_.numbered(5210) != 0.0)) {
    refuse_with_compensation(true, 0, "cannot change axis offsets with cutter radius comp");
    Block block;
    axis_offsets(block, saved.g92_applied ? kG92_3 : kG92_2);
  }
  spindle_ = saved.spindle;
  mist_ = saved.mist;
  flood_ = saved.flood;
}

// LinuxCNC's convert_cutter_compensation_on: G41/G42 take the radius of tool D (D0 or no D: the
// tool in the spindle) from the tool table, G41.1/G42.1 the diameter D itself.
void Interpreter::compensation_on(const Block& block, int code) {
  const int column = block.g_column[kGroupCutterComp];
  const bool left = code == kG41 || code == kG41_1;
  if (plane_ == Plane::kYZ) {
    fail(column, "cutter radius compensation allowed only in XY, XZ planes");
  }
  if (compensation_.on()) fail(column, "cannot turn cutter radius comp on when on");
  double radius = 0.0;
  if (code == kG41_1 || code == kG42_1) {
    if (!block.has('d')) fail(column, fmt::format("G{}.1 with no D word", code / 10));
    if (block.has('l')) {
      // L: a lathe tool's orientation, which needs G18; 0 and 9 are a mill's (no offset).
      const Word& l = block['l'];
      if (plane_ != Plane::kXZ) {
        fail(l.column, fmt::format("G{}.1 with L word, but plane is not G18", code / 10));
      }
      if (l.value != 0.0 && l.value != 9.0) {
        fail(l.column, "lathe tool orientations (L1 to L8 with G41.1, G42.1) are not supported");
      }
    }
    radius = block['d'].value / 2.0;
  } else {
    int tool = loaded_tool_;
    if (block.has('d')) {
      const Word& d = block['d'];
      const int number = static_cast<int>(d.value + 0.5);  // LinuxCNC's is_near_int
      if (std::abs(number - d.value) >= tol::kGcodeIntegerWord) {
        fail(d.column, fmt::format("G{} requires D word to be a whole number", code / 10));
      }
      if (number < 0) fail(d.column, "negative D word tool radius index used");
      if (number != 0) tool = number;
    }
    radius = tool_radius(tool, block.has('d') ? block['d'].column : column);
  }
  compensation_.turn_on(left ? gcode::CompensationSide::kLeft : gcode::CompensationSide::kRight,
                        radius, inches_);
  compensation_code_ = code;
}

// The radius of `tool` in program units; 0 for no tool (T0), as LinuxCNC's empty spindle.
double Interpreter::tool_radius(int tool, int column) {
  if (tool == 0) {
    if (first_warning("no tool radius")) {
      warn(line_, column,
           "cutter radius compensation with no tool in the spindle (tool 0): the radius is 0 and "
           "the path is not offset, as in LinuxCNC");
    }
    return 0.0;
  }
  const std::optional<double> diameter =
      options_.tool_diameter ? options_.tool_diameter(tool) : std::nullopt;
  if (!diameter) {
    fail(column, fmt::format("cutter radius compensation needs the diameter of tool {}, which is "
                             "not in the tool table (give one: --tools, or the job's \"tools\")",
                             tool));
  }
  return *diameter / 2.0 / scale();
}

// LinuxCNC's convert_cutter_compensation_off: the held moves are released, and the next move
// starts from the programmed point in the program's terms.
void Interpreter::compensation_off(int column) {
  const bool released =
      compensating(column, [&] { return compensation_.turn_off(to_plane(position_)); });
  if (released) position_ = from_plane(compensation_.programmed());
  compensation_code_ = kG40;
}

void Interpreter::note_unmodelled_codes(const Block& block) {
  if (block.m[kMGroupCoolant] != -1) {
    note_unmodelled("coolant (M7, M8, M9): no effect on the tip path",
                    block.m_column[kMGroupCoolant]);
  }
  if (block.g[kGroupNonModal] == kG4) {
    note_unmodelled("dwell (G4): the tool stands still; the tip path is unchanged",
                    block.g_column[kGroupNonModal]);
  }
  if (block.m[kMGroupStop] == 0 || block.m[kMGroupStop] == 1) {
    note_unmodelled("pauses (M0, M1): the program is read on", block.m_column[kMGroupStop]);
  }
  if (block.g[kGroupToolLength] != -1) {
    note_unmodelled(
        "tool length offsets (G43 H, G49): not applied; the program is read in tool "
        "tip coordinates, as with the right offset in effect",
        block.g_column[kGroupToolLength]);
  }
  if (block.g[kGroupPathControl] != -1) {
    note_unmodelled(
        "path control (G61, G61.1, G64 P Q): the programmed path is followed exactly; "
        "a machine in G64 may round corners by up to P",
        block.g_column[kGroupPathControl]);
  }
}

// LinuxCNC's convert_length_units: the current position, the offsets and the moves held by
// cutter compensation are converted; the feed rate stays the same physical rate (kept here in
// mm/min).
void Interpreter::set_units(bool inches) {
  if (inches == inches_) return;
  const double factor = inches ? 1.0 / kMillimetresPerInch : kMillimetresPerInch;
  position_ *= factor;
  origin_offset_ *= factor;
  axis_offset_ *= factor;
  compensation_.scale(factor, inches);
  inches_ = inches;
}

void Interpreter::publish_state() {
  parameters_.set_numbered(5400, static_cast<double>(loaded_tool_));
  for (int axis = 0; axis < 3; ++axis) parameters_.set_numbered(5420 + axis, position_[axis]);
  parameters_.set_position_readable(!compensation_.on());
}

// The motion the block will make (LinuxCNC's motion_to_be), -1 for none; `column` is the column
// to blame for it (its G word, or its first axis word when the motion is modal).
int Interpreter::motion_to_be(const Block& block, int& column) const {
  const int motion = block.g[kGroupMotion];
  const int zero = block.g[kGroupNonModal];
  // G10, G28, G30, G52 and G92 take the line's axis words for themselves (LinuxCNC's
  // enhance_block).
  const bool zero_takes_axes =
      zero == kG10 || zero == kG28 || zero == kG30 || zero == kG52 || zero == kG92;
  if (block.has_polar()) {
    const int at =
        block.polar_radius.present ? block.polar_radius.column : block.polar_angle.column;
    if (plane_ != Plane::kXY) fail(at, "cannot use polar coordinate except in G17 plane");
    if (block.has('x')) fail(at, "cannot specify both polar coordinate and X word");
    if (block.has('y')) fail(at, "cannot specify both polar coordinate and Y word");
    if (zero == kG53) fail(at, "cannot use polar coordinates with G53");
    if (zero == kG92 || zero == kG52 || zero == kG10 || zero == kG28 || zero == kG30) {
      fail(at, "polar coordinates can only be used for motion");
    }
  }
  const bool motion_words = block.has_axis() || block.has_polar();
  if ((zero == kG52 || zero == kG92) && !block.has_axis()) {
    fail(block.g_column[kGroupNonModal], fmt::format("all axes missing with {}", g_name(zero)));
  }
  if (motion != -1) {
    column = block.g_column[kGroupMotion];
    if (motion == kG80) {
      if (motion_words && !zero_takes_axes) {
        fail(block.has_axis() ? block.first_axis_column() : column,
             "cannot use axis values with G80");
      }
    } else if (zero_takes_axes) {
      fail(column, fmt::format("cannot use two G codes that both use axis values: {} and {}",
                               g_name(zero), g_name(motion)));
    } else if (!motion_words && is_cycle(motion)) {
      fail(column, fmt::format("all axes missing with motion code {}", g_name(motion)));
    }
    return motion;
  }
  if (zero_takes_axes || !motion_words) return -1;
  column = block.has_axis() ? block.first_axis_column()
                            : (block.polar_radius.present ? block.polar_radius.column
                                                          : block.polar_angle.column);
  if (motion_mode_ == kG80) {
    fail(column, "cannot use axis values without a G code that uses them (no motion mode)");
  }
  return motion_mode_;
}

// LinuxCNC's check_other_codes, for the words cwe reads.
void Interpreter::check_words(const Block& block, int motion) const {
  const bool arc = motion == kG2 || motion == kG3;
  const bool synchronised = motion == kG33 || motion == kG33_1;
  const bool spline = motion == kG5 || motion == kG5_1;
  if (block.has('i') && !arc && !spline && motion != kG33_1) {
    fail(block['i'].column, "I word with no G2, G3, G5, G5.1 or G33.1 to use it");
  }
  if (block.has('j') && !arc && !spline) {
    fail(block['j'].column, "J word with no G2, G3, G5 or G5.1 to use it");
  }
  if (block.has('k') && !arc && !synchronised) {
    fail(block['k'].column, "K word with no G2, G3, G33 or G33.1 to use it");
  }
  if (synchronised && !block.has('k')) {
    fail(block.g[kGroupMotion] != -1 ? block.g_column[kGroupMotion] : block.first_axis_column(),
         "K word missing with G33/G33.1");
  }
  if (synchronised && block.has('f')) fail(block['f'].column, "F word used with a G33/G33.1");
  const bool g10 = block.g[kGroupNonModal] == kG10;
  if (g10) {
    if (!block.has('l'))
      fail(block.g_column[kGroupNonModal], "line with G10 does not have L2 or L20");
    if (!block.has('p'))
      fail(block.g_column[kGroupNonModal], "line with G10 does not have a P word");
  }
  if (block.has('r') && !arc && !is_cycle(motion) && !g10) {
    fail(block['r'].column, "R word with no G2, G3 or canned cycle to use it");
  }
  if (block.has('p') && !arc && motion != kG5 && motion != kG82 && block.g[kGroupNonModal] != kG4 &&
      !g10 && block.g[kGroupPathControl] != kG64) {
    fail(block['p'].column, "P word with no G2, G3, G4, G5, G64 or G82 to use it");
  }
  const bool m61 = block.m[kMGroupToolChange] == 61;
  if (m61 && !block.has('q')) fail(block.m_column[kMGroupToolChange], "need Q parameter with M61");
  if (m61 && (block['q'].value < 0.0 ||
              std::abs(block['q'].value - std::round(block['q'].value)) > tol::kGcodeIntegerWord)) {
    fail(block['q'].column, "Q value with M61 must be a tool number, 0 or more");
  }
  if (block.has('q') && motion != kG5 && motion != kG73 && motion != kG83 &&
      block.g[kGroupPathControl] != kG64 && !m61) {
    fail(block['q'].column, "Q word with no G5, G64, G73, G83 or M61 to use it");
  }
  const int comp = block.g[kGroupCutterComp];
  if (block.has('l') && !is_cycle(motion) && !g10 && comp != kG41_1 && comp != kG42_1) {
    fail(block['l'].column, "L word with no canned cycle to use it");
  }
  if (block.has('d') && comp != kG41 && comp != kG42 && comp != kG41_1 && comp != kG42_1) {
    fail(block['d'].column, "D word with no G41, G41.1, G42 or G42.1 to use it");
  }
  if (block.has('h') && block.g[kGroupToolLength] != kG43) {
    fail(block['h'].column, "H word with no G43 to use it");
  }
  if (block.g[kGroupNonModal] == kG4 && !block.has('p')) {
    fail(block.g_column[kGroupNonModal], "dwell time missing with G4 (P word)");
  }
  if (block.g[kGroupNonModal] == kG4 && block['p'].value < 0.0) {
    fail(block['p'].column, "negative dwell time (P word) with G4");
  }
  if (arc && block.has('p')) {
    const double p = block['p'].value;
    if (std::abs(p - std::round(p)) > tol::kGcodeArcTurns) {
      fail(block['p'].column, fmt::format("P value not an integer with G2 or G3: {}", p));
    }
    if (std::round(p) < 1.0) {
      fail(block['p'].column, "P value should be 1 or greater with G2 or G3");
    }
  }
}

bool Interpreter::execute(const Block& block) {
  // Parameters set on the line take their values now, in order: the line's words were read
  // with the old ones (LinuxCNC's parallel setting).
  for (const gcode::ParameterSetting& setting : block.settings) {
    if (setting.index > 0) {
      parameters_.set_numbered(setting.index, setting.value);
    } else {
      parameters_.set_named(setting.name, setting.value);
    }
  }
  int motion_column = 0;
  const int motion = motion_to_be(block, motion_column);
  check_words(block, motion);

  // LinuxCNC's order of execution within a line: F, S, T, M6, M3/M4/M5, M7/M8/M9, G4, plane,
  // units, G40, G43/G49, G54, G61/G64, G90/G91, G90.1/G91.1, G98/G99, motion, M0/M1/M2/M30.
  if (block.has('f')) feed_mm_per_min_ = block['f'].value * scale();  // canon's SET_FEED_RATE
  if (block.has('s')) spindle_speed_ = block['s'].value;
  if (block.has('t')) selected_tool_ = static_cast<int>(block['t'].value);
  refuse_with_compensation(block.m[kMGroupToolChange] == 6, block.m_column[kMGroupToolChange],
                           "cannot change tools with cutter radius compensation on");
  if (block.m[kMGroupToolChange] == 6) {
    // M6 loads the selected tool and stops the spindle (LinuxCNC's convert_tool_change). The
    // interpreter then takes the position from the machine: where the last move ended, which
    // after G40 is not the programmed point it had.
    loaded_tool_ = selected_tool_;
    result_.tool_changes.push_back({loaded_tool_, SourceLocation{source_, line_, 1}});
    spindle_ = SpindleDirection::kStopped;
    position_ = (tip_ + frame_offset_) / scale() - origin_offset_ - axis_offset_;
  } else if (block.m[kMGroupToolChange] == 61) {
    // M61 Q: the spindle holds tool Q from now on, without a change (the spindle keeps turning).
    loaded_tool_ = static_cast<int>(std::lround(block['q'].value));
    result_.tool_changes.push_back(
        {loaded_tool_, SourceLocation{source_, line_, block.m_column[kMGroupToolChange]}});
  }
  switch (block.m[kMGroupSpindle]) {
    case 70:  // save the modal state in this call level (M73: and restore it on return)
    case 73:
      frames_.back().state = modal_state();
      if (block.m[kMGroupSpindle] == 73 && frames_.size() > 1) {
        frames_.back().restore_on_return = true;
      }
      break;
    case 71:
      frames_.back().state.reset();
      break;
    case 72:
      if (!frames_.back().state) {
        fail(block.m_column[kMGroupSpindle],
             "cannot restore context from invalid stack frame - missing M70/M73?");
      }
      restore(*frames_.back().state);
      break;
    case 3:
      spindle_ = SpindleDirection::kClockwise;
      break;
    case 4:
      spindle_ = SpindleDirection::kCounterClockwise;
      break;
    case 5:
      spindle_ = SpindleDirection::kStopped;
      break;
    default:
      break;
  }
  switch (block.m[kMGroupCoolant]) {
    case 7:
      mist_ = true;
      break;
    case 8:
      flood_ = true;
      break;
    case 9:
      mist_ = flood_ = false;
      break;
    default:
      break;
  }
  // M7, M8, M9 (coolant), G4 (dwell), G43/G49, G54, G61/G61.1/G64, G94, G97: accepted, no
  // effect on the tip path.
  if (block.g[kGroupPlane] != -1) {
    const int code = block.g[kGroupPlane];
    const Plane plane = code == kG17 ? Plane::kXY : (code == kG18 ? Plane::kXZ : Plane::kYZ);
    refuse_with_compensation(plane != plane_, block.g_column[kGroupPlane],
                             "cannot change planes with cutter radius compensation on");
    plane_ = plane;
  }
  if (block.g[kGroupUnits] != -1) {
    const bool inches = block.g[kGroupUnits] == kG20;
    if (!units_seen_) {
      units_seen_ = true;
      result_.units = inches ? ProgramUnits::kInches : ProgramUnits::kMillimetres;
    }
    set_units(inches);
  }
  if (block.g[kGroupCutterComp] == kG40) {
    compensation_off(block.g_column[kGroupCutterComp]);
  } else if (block.g[kGroupCutterComp] != -1) {
    compensation_on(block, block.g[kGroupCutterComp]);
  }
  refuse_with_compensation(block.g[kGroupCoordSystem] != -1, block.g_column[kGroupCoordSystem],
                           "cannot change coordinate systems with cutter radius compensation on");
  refuse_with_compensation(block.g[kGroupPathControl] != -1, block.g_column[kGroupPathControl],
                           "cannot change control mode with cutter radius compensation on");
  refuse_with_compensation(block.g[kGroupRetract] != -1, block.g_column[kGroupRetract],
                           "cannot change retract mode with cutter radius compensation on");
  if (block.g[kGroupCoordSystem] != -1) {
    // G54 … G59 are 1 … 6, G59.1 … G59.3 are 7 … 9.
    const int code = block.g[kGroupCoordSystem];
    select_origin(code < 591 ? (code - 530) / 10 : code - 584);
  }
  if (block.g[kGroupDistance] != -1) incremental_ = block.g[kGroupDistance] == kG91;
  if (block.g[kGroupArcDistance] != -1) arc_absolute_ = block.g[kGroupArcDistance] == kG90_1;
  if (block.g[kGroupRetract] != -1) retract_to_r_ = block.g[kGroupRetract] == kG99;
  const int zero = block.g[kGroupNonModal];
  const int zero_column = block.g_column[kGroupNonModal];
  refuse_with_compensation(zero == kG28 || zero == kG30, zero_column,
                           "cannot use G28 or G30 with cutter radius comp");
  refuse_with_compensation(zero == kG28_1 || zero == kG30_1, zero_column,
                           "cannot set reference point with cutter compensation in effect");
  refuse_with_compensation(
      zero == kG52 || zero == kG92 || zero == kG92_1 || zero == kG92_2 || zero == kG92_3,
      zero_column, "cannot change axis offsets with cutter radius comp");
  switch (zero) {  // LinuxCNC's convert_modal_0, before the motion
    case kG10:
      setup_offsets(block);
      break;
    case kG28:
    case kG30:
      go_home(block, block.g[kGroupNonModal]);
      break;
    case kG28_1:
    case kG30_1: {
      const Vec3 at = machine_mm(position_);
      const int first = block.g[kGroupNonModal] == kG28_1 ? 5161 : 5181;
      for (int a = 0; a < 3; ++a) parameters_.set_numbered(first + a, at[a]);
      break;
    }
    case kG52:
    case kG92:
    case kG92_1:
    case kG92_2:
    case kG92_3:
      axis_offsets(block, block.g[kGroupNonModal]);
      break;
    default:
      break;
  }

  if (block.g[kGroupNonModal] == kG53 && motion != kG0 && motion != kG1) {
    fail(block.g_column[kGroupNonModal], "must use G0 or G1 with G53");
  }
  if (motion != -1) {
    // Any motion other than a canned cycle ends a run of cycles (the G98 initial level).
    if (!is_cycle(motion)) cycle_initial_level_set_ = false;
    if (motion == kG0 || motion == kG1) {
      straight(block, motion, motion_column);
    } else if (motion == kG33 || motion == kG33_1) {
      synchronised(block, motion, motion_column);
    } else if (motion == kG5 || motion == kG5_1) {
      spline(block, motion, motion_column);
    } else if (motion == kG2 || motion == kG3) {
      arc(block, motion, motion_column);
    } else if (motion == kG80) {
      motion_mode_ = kG80;
    } else {
      cycle(block, motion, motion_column);
    }
  }
  note_unmodelled_codes(block);
  const int stop = block.m[kMGroupStop];
  if (stop == 0 || stop == 1) {
    compensating(block.m_column[kMGroupStop], [&] { compensation_.release(to_plane(position_)); });
  } else if (stop != -1) {
    compensating(block.m_column[kMGroupStop], [&] { compensation_.stop(to_plane(position_)); });
    compensation_code_ = kG40;
  }
  if (stop == 99) {
    // M99 in the main program: LinuxCNC starts the program over, forever.
    warn(line_, block.m_column[kMGroupStop],
         "M99 in the main program: LinuxCNC would run the program again and again; cwe reads it "
         "once, as if M99 were M30");
  }
  return stop != 2 && stop != 30 && stop != 99;  // M0, M1 (pauses) do not change the path
}

}  // namespace cwe::gcode
