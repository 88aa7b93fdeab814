#pragma once
// Parameters and expressions of RS274NGC as LinuxCNC 2.9 reads them (interp_read.cc:
// read_real_value, read_real_expression, read_operation, read_operation_unary, read_unary,
// read_atan, read_parameter, read_parameter_setting; interp_execute.cc: execute_binary,
// execute_unary; interp_namedparams.cc). Private to the G-code reader.
//
// A value is a number, a parameter (#5, ##2, #[1+2], #<name>), a unary function (SIN[30],
// ATAN[1]/[2], EXISTS[#<x>]) or a bracketed expression; a sign may precede any of them.
// Expressions are evaluated left to right within six precedence levels, as LinuxCNC's stack
// machine does: ** above * / MOD above + - above EQ NE GT GE LT LE above AND OR XOR. Angles are in
// degrees. EQ and NE compare within 0.0001 (LinuxCNC's TOLERANCE_EQUAL); LE, GE, LT and GT are
// exact, as in 2.9.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cwe/core/error.hpp"

namespace cwe::gcode {

// A line with comments and blanks removed and letters lowered (LinuxCNC's close_and_downcase),
// each remaining character with its column (1-based byte offset) in the original line.
struct CompactLine {
  std::string code;
  std::vector<int> columns;
  bool comment_first = false;  // a comment precedes the first word (so N cannot be first)

  // The column of code[i]; one past the last character for the end of the line.
  int column(std::size_t i) const {
    if (i < columns.size()) return columns[i];
    return columns.empty() ? 1 : columns.back() + 1;
  }
  char at(std::size_t i) const { return i < code.size() ? code[i] : '\0'; }
};

// A number as LinuxCNC writes it (read_real_number) at code[i]: an optional sign, digits with at
// most one decimal point, no exponent. `end` is past it; the caller words its own errors.
struct PlainNumber {
  enum class Status { kOk, kNoDigits, kTwoPoints, kOutOfRange, kBad };
  Status status = Status::kOk;
  double value = 0.0;
  std::size_t end = 0;
};
PlainNumber scan_number(const std::string& code, std::size_t i);

// Numbered parameters #1 … #5601, named parameters — global when the name starts with '_',
// otherwise local to the current subroutine call — and the interpreter's predefined read-only
// ones (#<_x>, #<_metric>, …), which it supplies through a lookup.
class Parameters {
 public:
  static constexpr int kNumbered = 5602;  // LinuxCNC's RS274NGC_MAX_PARAMETERS: #1 … #5601

  Parameters();

  double numbered(int index) const { return numbered_[static_cast<std::size_t>(index)]; }
  void set_numbered(int index, double value) { numbered_[static_cast<std::size_t>(index)] = value; }
  // LinuxCNC's read-only numbers: the tool's data #5400–#5413 and the position #5420–#5428.
  static bool read_only(int index) {
    return (index >= 5400 && index <= 5413) || (index >= 5420 && index <= 5428);
  }

  // The position #5420–#5428 cannot be read under cutter radius compensation (LinuxCNC: the
  // compensated point is not known until the next move).
  bool position_readable() const { return position_readable_; }
  void set_position_readable(bool readable) { position_readable_ = readable; }

  // Named parameters by their lower-case name (without < >); nullopt when not defined.
  std::optional<double> named(std::string_view name) const;
  // Throws nothing: the caller checks read_only_name first.
  void set_named(const std::string& name, double value);
  bool read_only_name(std::string_view name) const;

  using Lookup = std::function<std::optional<double>(std::string_view name)>;
  void set_predefined(Lookup lookup) { predefined_ = std::move(lookup); }

  // A subroutine call opens a scope of local named parameters; its return closes it.
  void push_locals() { locals_.emplace_back(); }
  void pop_locals() {
    if (locals_.size() > 1) locals_.pop_back();
  }

 private:
  using Names = std::map<std::string, double, std::less<>>;
  std::vector<double> numbered_;
  Names globals_;
  std::vector<Names> locals_;
  Lookup predefined_;
  bool position_readable_ = true;
};

// A parameter setting read from a line (#3=6, #<depth>=[#1*2]): applied after the whole line
// has been read, in order, so the line's words see the old values (LinuxCNC sets parameters in
// parallel).
struct ParameterSetting {
  int index = 0;     // numbered; 0 for a named one
  std::string name;  // named
  double value = 0.0;
};

// Reads values from a compacted line. Errors are InputErrors at `where` (source and line) with
// the column of the offending character.
class ValueReader {
 public:
  ValueReader(const CompactLine& line, const SourceLocation& where, const Parameters& parameters)
      : line_(line), where_(where), parameters_(parameters) {}

  // LinuxCNC's read_real_value at code[i], advancing i past the value.
  double real(std::size_t& i) const;
  // LinuxCNC's read_integer_value: a value within 0.0001 of an integer.
  int integer(std::size_t& i) const;
  // A parameter setting at code[i] == '#' (LinuxCNC's read_parameter_setting).
  ParameterSetting setting(std::size_t& i) const;
  // A bracketed expression at code[i] == '['.
  double expression(std::size_t& i) const;
  // A name at code[i] == '<', to the next '>' (named parameters, o<name>).
  std::string name(std::size_t& i) const;

  [[noreturn]] void fail(std::size_t i, const std::string& message) const;

 private:
  double number(std::size_t& i) const;
  double parameter(std::size_t& i, bool check_exists) const;
  double unary(std::size_t& i) const;

  const CompactLine& line_;
  const SourceLocation& where_;
  const Parameters& parameters_;
};

}  // namespace cwe::gcode
