// The G-code interpreter (gcode_interpreter.hpp): work coordinate systems, G10 L2/L20, G92 and G52,
// G28 and G30, and the machine definition.

#include "gcode_interpreter.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"
#include "gcode_tolerance.hpp"

namespace cwe::gcode {

Vec3 Interpreter::stored_offset(int first) const {
  return Vec3(parameters_.numbered(first), parameters_.numbered(first + 1),
              parameters_.numbered(first + 2)) /
         scale();
}

void Interpreter::set_stored_offset(int first, const Vec3& offset) {
  for (int a = 0; a < 3; ++a) parameters_.set_numbered(first + a, offset[a] * scale());
}

// LinuxCNC's convert_coordinate_system: the tip stays where it is, its coordinates change.
void Interpreter::select_origin(int origin) {
  if (origin == origin_index_) return;
  const Vec3 offset = stored_offset(5201 + 20 * origin);
  if (parameters_.numbered(5210 + 20 * origin) != 0.0) {
    fail(1, fmt::format(
                "G{}: coordinate system rotation (G10 L2 R) is not supported",
                origin < 7 ? fmt::format("{}", 53 + origin) : fmt::format("59.{}", origin - 6)));
  }
  position_ += origin_offset_ - offset;
  origin_offset_ = offset;
  origin_index_ = origin;
  parameters_.set_numbered(5220, origin);
}

// LinuxCNC's convert_setup: G10 L2 sets a coordinate system's offsets, G10 L20 sets them so that
// the current point has the given coordinates in it.
void Interpreter::setup_offsets(const Block& block) {
  const int column = block.g_column[kGroupNonModal];
  const int l = static_cast<int>(block['l'].value);
  if (l == 1 || l == 10 || l == 11) {
    // Tool table data (length, radius, orientation): nothing on the tip path cwe reads changes
    // (tool length offsets are not applied; cutter compensation is not read).
    if (!(block['p'].value >= 1.0)) {
      fail(block['p'].column, fmt::format("G10 L{} needs a tool number P of 1 or more", l));
    }
    if (first_warning("tool data")) {
      warn(line_, column,
           fmt::format("G10 L{} (tool table data) changes nothing on the tip path "
                       "cwe reads; later G10 L1, L10 and L11 lines say nothing",
                       l));
    }
    return;
  }
  if (l != 2 && l != 20) fail(block['l'].column, fmt::format("G10 L{}: expected L2 or L20", l));
  const double p_value = block['p'].value;
  int p = static_cast<int>(p_value + 0.0001);
  if (!(p_value >= 0.0) || p > 9 || std::abs(p_value - p) > 0.0001) {
    fail(block['p'].column,
         fmt::format("P value out of range with G10 L{}: {:g} (expected 0 to 9)", l, p_value));
  }
  if (p == 0) p = origin_index_;
  refuse_with_compensation(
      p == origin_index_, block['p'].column,
      "cannot change the active coordinate system with cutter radius compensation on");
  if (block.has('r') && block['r'].value != 0.0) {
    fail(block['r'].column, "coordinate system rotation (G10 L2 R) is not supported");
  }
  const int first = 5201 + 20 * p;
  Vec3 offset = stored_offset(first);
  // The current point in system p (LinuxCNC's find_current_in_system).
  const Vec3 here = position_ + origin_offset_ - offset;
  for (int a = 0; a < 3; ++a) {
    const Word& w = block[static_cast<char>('x' + a)];
    if (!w.present) continue;
    offset[a] = l == 2 ? w.value : here[a] + offset[a] - w.value;
  }
  set_stored_offset(first, offset);
  if (p == origin_index_) {
    position_ += origin_offset_ - offset;
    origin_offset_ = offset;
  }
}

// LinuxCNC's convert_axis_offsets: G92 makes the current point have the given coordinates, G52
// offsets by the given values; G92.1 and G92.2 clear the offsets (G92.1 also their parameters),
// G92.3 restores them from #5211-#5213.
void Interpreter::axis_offsets(const Block& block, int code) {
  if (code == kG52 || code == kG92) {
    parameters_.set_numbered(5210, 1.0);
    for (int a = 0; a < 3; ++a) {
      const Word& w = block[static_cast<char>('x' + a)];
      if (!w.present) continue;
      if (code == kG52) {
        position_[a] += axis_offset_[a] - w.value;
        axis_offset_[a] = w.value;
      } else {
        axis_offset_[a] = position_[a] + axis_offset_[a] - w.value;
        position_[a] = w.value;
      }
    }
    set_stored_offset(5211, axis_offset_);
    return;
  }
  if (code == kG92_1 || code == kG92_2) {
    parameters_.set_numbered(5210, 0.0);
    position_ += axis_offset_;
    axis_offset_ = Vec3::Zero();
    if (code == kG92_1) set_stored_offset(5211, Vec3::Zero());
    return;
  }
  // G92.3
  parameters_.set_numbered(5210, 1.0);
  const Vec3 offset = stored_offset(5211);
  position_ += axis_offset_ - offset;
  axis_offset_ = offset;
}

// LinuxCNC's convert_home: a rapid to the line's point (current coordinates), then to the stored
// home position (#5161-#5163 for G28, #5181-#5183 for G30, machine coordinates) for the axes
// named, or all of them when none is.
void Interpreter::go_home(const Block& block, int code) {
  warn_machine(code == kG28 ? "G28 (go to the stored home position)"
                            : "G30 (go to the stored position)");
  Vec3 end = find_end(block);
  emit_line(MotionMode::kRapid, end);
  const Vec3 home = stored_offset(code == kG28 ? 5161 : 5181) - origin_offset_ - axis_offset_;
  const bool any = block.has_axis();
  for (int a = 0; a < 3; ++a) {
    if (!any || block[static_cast<char>('x' + a)].present) end[a] = home[a];
  }
  emit_line(MotionMode::kRapid, end);
}

// The machine's offsets and stored positions become LinuxCNC's parameters; G54 is selected.
void Interpreter::set_up_machine(const MachineDefinition& machine) {
  for (int k = 0; k < 9; ++k) set_stored_offset(5221 + 20 * k, machine.work_offsets[k] / scale());
  set_stored_offset(5161, machine.g28 / scale());
  set_stored_offset(5181, machine.g30 / scale());
  origin_offset_ = stored_offset(5221);
  frame_offset_ = machine.work_offsets[static_cast<std::size_t>(machine.frame - 1)];
}

void Interpreter::warn_machine(const char* what) {
  if (options_.machine || !first_warning("machine")) return;
  warn(line_, 0,
       fmt::format("{}: machine coordinates are taken equal to the program's with "
                   "zero work offsets and no tool length offset (the stored positions "
                   "#5161-#5186 start at 0, as in LinuxCNC without a parameter file)",
                   what));
}

}  // namespace cwe::gcode
