// The G-code interpreter (gcode_interpreter.hpp): the program's lines, reading a line into a block
// (LinuxCNC's interp_read.cc), and the public functions of cwe/toolpath/gcode_reader.hpp.

#include "cwe/toolpath/gcode_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"
#include "gcode_interpreter.hpp"
#include "gcode_tolerance.hpp"

namespace cwe {
namespace gcode {
namespace {

struct CodeInfo {
  int code;  // ×10 for G codes
  int group;
  const char* unsupported;  // nullptr: supported; otherwise why not ("... is not supported")
};

// Every G code LinuxCNC 2.9 knows (its _gees table), with the subset cwe reads.
constexpr CodeInfo kGCodes[] = {
    {0, kGroupMotion, nullptr},
    {10, kGroupMotion, nullptr},
    {20, kGroupMotion, nullptr},
    {30, kGroupMotion, nullptr},
    {40, kGroupNonModal, nullptr},
    {50, kGroupMotion, nullptr},
    {51, kGroupMotion, nullptr},
    {52, kGroupMotion, "NURBS (G5.2, G5.3) are"},
    {53, kGroupMotion, "NURBS (G5.2, G5.3) are"},
    {70, kGroupLathe, "lathe diameter mode (G7) is"},
    {80, kGroupLathe, nullptr},  // radius mode: the default, nothing to change
    {100, kGroupNonModal, nullptr},
    {170, kGroupPlane, nullptr},
    {171, kGroupPlane, "UVW planes (G17.1, G18.1, G19.1) are"},
    {180, kGroupPlane, nullptr},
    {181, kGroupPlane, "UVW planes (G17.1, G18.1, G19.1) are"},
    {190, kGroupPlane, nullptr},
    {191, kGroupPlane, "UVW planes (G17.1, G18.1, G19.1) are"},
    {200, kGroupUnits, nullptr},
    {210, kGroupUnits, nullptr},
    {280, kGroupNonModal, nullptr},
    {281, kGroupNonModal, nullptr},
    {300, kGroupNonModal, nullptr},
    {301, kGroupNonModal, nullptr},
    {330, kGroupMotion, nullptr},
    {331, kGroupMotion, nullptr},
    {382, kGroupMotion, "probing (G38.2 to G38.5) is"},
    {383, kGroupMotion, "probing (G38.2 to G38.5) is"},
    {384, kGroupMotion, "probing (G38.2 to G38.5) is"},
    {385, kGroupMotion, "probing (G38.2 to G38.5) is"},
    {400, kGroupCutterComp, nullptr},
    {410, kGroupCutterComp, nullptr},
    {411, kGroupCutterComp, nullptr},
    {420, kGroupCutterComp, nullptr},
    {421, kGroupCutterComp, nullptr},
    {430, kGroupToolLength, nullptr},
    {431, kGroupToolLength, "dynamic tool length offsets (G43.1, G43.2) are"},
    {432, kGroupToolLength, "dynamic tool length offsets (G43.1, G43.2) are"},
    {490, kGroupToolLength, nullptr},
    {520, kGroupNonModal, nullptr},
    {530, kGroupNonModal, nullptr},
    {540, kGroupCoordSystem, nullptr},
    {550, kGroupCoordSystem, nullptr},
    {560, kGroupCoordSystem, nullptr},
    {570, kGroupCoordSystem, nullptr},
    {580, kGroupCoordSystem, nullptr},
    {590, kGroupCoordSystem, nullptr},
    {591, kGroupCoordSystem, nullptr},
    {592, kGroupCoordSystem, nullptr},
    {593, kGroupCoordSystem, nullptr},
    {610, kGroupPathControl, nullptr},
    {611, kGroupPathControl, nullptr},
    {640, kGroupPathControl, nullptr},
    {700, kGroupMotion, "lathe finishing and roughing cycles (G70, G71, G72) are"},
    {710, kGroupMotion, "lathe finishing and roughing cycles (G70, G71, G72) are"},
    {711, kGroupMotion, "lathe finishing and roughing cycles (G70, G71, G72) are"},
    {720, kGroupMotion, "lathe finishing and roughing cycles (G70, G71, G72) are"},
    {721, kGroupMotion, "lathe finishing and roughing cycles (G70, G71, G72) are"},
    {730, kGroupMotion, nullptr},
    {740, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {760, kGroupMotion, "threading (G76) is"},
    {800, kGroupMotion, nullptr},
    {810, kGroupMotion, nullptr},
    {820, kGroupMotion, nullptr},
    {830, kGroupMotion, nullptr},
    {840, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {850, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {860, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {870, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {880, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {890, kGroupMotion, "canned cycles other than G73, G81, G82 and G83 are"},
    {900, kGroupDistance, nullptr},
    {901, kGroupArcDistance, nullptr},
    {910, kGroupDistance, nullptr},
    {911, kGroupArcDistance, nullptr},
    {920, kGroupNonModal, nullptr},
    {921, kGroupNonModal, nullptr},
    {922, kGroupNonModal, nullptr},
    {923, kGroupNonModal, nullptr},
    {930, kGroupFeedMode, "inverse time feed (G93) is"},
    {940, kGroupFeedMode, nullptr},
    {950, kGroupFeedMode, "feed per revolution (G95) is"},
    {960, kGroupSpindleMode, "constant surface speed (G96) is"},
    {970, kGroupSpindleMode, nullptr},
    {980, kGroupRetract, nullptr},
    {990, kGroupRetract, nullptr},
};

// The M codes LinuxCNC 2.9 knows below M100 (its _ems table).
constexpr CodeInfo kMCodes[] = {
    {0, kMGroupStop, nullptr},
    {1, kMGroupStop, nullptr},
    {2, kMGroupStop, nullptr},
    {3, kMGroupSpindle, nullptr},
    {4, kMGroupSpindle, nullptr},
    {5, kMGroupSpindle, nullptr},
    {6, kMGroupToolChange, nullptr},
    {7, kMGroupCoolant, nullptr},
    {8, kMGroupCoolant, nullptr},
    {9, kMGroupCoolant, nullptr},
    {19, kMGroupSpindle, "spindle orientation (M19) is"},
    {30, kMGroupStop, nullptr},
    {48, 9, "override switches (M48 to M53) are"},
    {49, 9, "override switches (M48 to M53) are"},
    {50, 9, "override switches (M48 to M53) are"},
    {51, 9, "override switches (M48 to M53) are"},
    {52, 9, "override switches (M48 to M53) are"},
    {53, 9, "override switches (M48 to M53) are"},
    {60, kMGroupStop, "pallet changes (M60) are"},
    {61, kMGroupToolChange, nullptr},
    {62, 5, "digital and analog I/O (M62 to M68) is"},
    {63, 5, "digital and analog I/O (M62 to M68) is"},
    {64, 5, "digital and analog I/O (M62 to M68) is"},
    {65, 5, "digital and analog I/O (M62 to M68) is"},
    {66, 5, "digital and analog I/O (M62 to M68) is"},
    {67, 5, "digital and analog I/O (M62 to M68) is"},
    {68, 5, "digital and analog I/O (M62 to M68) is"},
    {70, kMGroupSpindle, nullptr},
    {71, kMGroupSpindle, nullptr},
    {72, kMGroupSpindle, nullptr},
    {73, kMGroupSpindle, nullptr},
    {98, 10, nullptr},           // read as an O-word when first on its line (read_m98)
    {99, kMGroupStop, nullptr},  // likewise inside a subprogram; in the main program, its end
};

template <std::size_t N>
const CodeInfo* find_code(const CodeInfo (&table)[N], int code) {
  for (const CodeInfo& info : table) {
    if (info.code == code) return &info;
  }
  return nullptr;
}

// A character for a message: itself if printable ASCII, its code otherwise.
std::string describe_char(unsigned char c) {
  if (c >= 0x21 && c < 0x7f) return fmt::format("'{}'", static_cast<char>(c));
  return fmt::format("0x{:02X}", static_cast<unsigned>(c));
}

}  // namespace

CompactLine Interpreter::compact(std::string_view raw) const {
  CompactLine out;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const char c = raw[i];
    if (c == ' ' || c == '\t') continue;
    if (c == ';') break;  // the rest of the line is a comment
    if (c == '(') {
      std::size_t j = i + 1;
      while (j < raw.size() && raw[j] != ')') {
        if (raw[j] == '(') fail(static_cast<int>(j + 1), "nested comment found");
        ++j;
      }
      if (j == raw.size()) fail(static_cast<int>(i + 1), "unclosed comment found");
      if (out.code.empty()) out.comment_first = true;
      i = j;
      continue;
    }
    out.code.push_back(c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c);
    out.columns.push_back(static_cast<int>(i + 1));
  }
  return out;
}

// A real number as LinuxCNC writes it: optional sign, digits with at most one decimal point, at
// least one digit; no exponent (E is a word letter). Spaces inside were removed by compact().
double Interpreter::read_number(const CompactLine& line, std::size_t& i, int word_column,
                                char letter) const {
  const std::string& s = line.code;
  const char upper = static_cast<char>(letter - 'a' + 'A');
  // A parameter, expression, unary function or a sign before one of them: LinuxCNC's
  // read_real_value.
  const char c = line.at(i), c1 = line.at(i + 1);
  const bool sign = c == '+' || c == '-';
  const bool signed_value = sign && c1 != '\0' && !(c1 >= '0' && c1 <= '9') && c1 != '.';
  if (c == '[' || c == '#' || (c >= 'a' && c <= 'z') || signed_value) {
    const double value = values(line).real(i);
    if (!(std::abs(value) <= kLargestInputValue)) {
      fail(word_column,
           fmt::format("{} value out of range (larger than {:g})", upper, kLargestInputValue));
    }
    return value;
  }
  const gcode::PlainNumber n = gcode::scan_number(s, i);
  switch (n.status) {
    case gcode::PlainNumber::Status::kOk:
      i = n.end;
      return n.value;
    case gcode::PlainNumber::Status::kNoDigits:
      fail(word_column, fmt::format("bad number format: {} needs a number", upper));
    case gcode::PlainNumber::Status::kTwoPoints:
      fail(word_column,
           fmt::format("bad number format: {} has more than one decimal point", upper));
    case gcode::PlainNumber::Status::kOutOfRange:
      fail(word_column,
           fmt::format("{} value out of range (larger than {:g})", upper, kLargestInputValue));
    case gcode::PlainNumber::Status::kBad:
      break;
  }
  fail(word_column, fmt::format("bad number format after {}", upper));
}

// LinuxCNC's read_integer_value: a real within kGcodeIntegerWord of an integer.
int Interpreter::read_integer(const CompactLine& line, std::size_t& i, int word_column,
                              char letter) const {
  const double value = read_number(line, i, word_column, letter);
  const double nearest = std::round(value);
  if (std::abs(value - nearest) > tol::kGcodeIntegerWord) {
    fail(word_column,
         fmt::format("non-integer value for {}: {}", static_cast<char>(letter - 'a' + 'A'), value));
  }
  return static_cast<int>(nearest);
}

void Interpreter::read_g(const CompactLine& line, std::size_t& i, int column, Block& block) const {
  const double value = read_number(line, i, column, 'g');
  // LinuxCNC's read_g: ten times the number, within a thousandth of an integer.
  const double tenths = 10.0 * value;
  double code = std::floor(tenths);
  if (tenths - code > 1.0 - tol::kGcodeGNumberTenths) {
    code += 1.0;
  } else if (tenths - code > tol::kGcodeGNumberTenths) {
    fail(column, fmt::format("G code out of range: G{}", value));
  }
  if (code > 999.0) fail(column, fmt::format("G code out of range: G{}", value));
  if (code < 0.0) fail(column, "negative G code used");
  const int number = static_cast<int>(code);
  const CodeInfo* info = find_code(kGCodes, number);
  if (info == nullptr) fail(column, fmt::format("unknown G code: {}", g_name(number)));
  if (info->unsupported != nullptr) {
    fail(column, fmt::format("{}: {} not supported", g_name(number), info->unsupported));
  }
  int& slot = block.g[static_cast<std::size_t>(info->group)];
  // G80 with another motion code on the line is ignored, as in LinuxCNC.
  if (number == kG80 && slot != -1) return;
  if (slot != -1 && slot != kG80) {
    fail(column, fmt::format("two G codes used from the same modal group: {} and {}", g_name(slot),
                             g_name(number)));
  }
  slot = number;
  block.g_column[static_cast<std::size_t>(info->group)] = column;
}

void Interpreter::read_m(const CompactLine& line, std::size_t& i, int column, Block& block) const {
  const int number = read_integer(line, i, column, 'm');
  if (number < 0) fail(column, "negative M code used");
  if (number > 199) fail(column, fmt::format("M code greater than 199: M{}", number));
  if (number >= 100) {
    fail(column, fmt::format("M{}: user-defined M codes (M100 to M199) are not supported", number));
  }
  const CodeInfo* info = find_code(kMCodes, number);
  if (info == nullptr) fail(column, fmt::format("unknown M code: M{}", number));
  if (number == 98) fail(column, "M98 must be the first word of its line");
  if (info->unsupported != nullptr) {
    fail(column, fmt::format("M{}: {} not supported", number, info->unsupported));
  }
  int& slot = block.m[static_cast<std::size_t>(info->group)];
  if (slot != -1) {
    fail(column,
         fmt::format("two M codes used from the same modal group: M{} and M{}", slot, number));
  }
  slot = number;
  block.m_column[static_cast<std::size_t>(info->group)] = column;
}

std::size_t Interpreter::after_line_number(const CompactLine& line) const {
  const std::string& s = line.code;
  std::size_t i = 0;
  // A leading '/' is block delete; LinuxCNC executes the line when the block-delete switch is
  // off, its default.
  if (i < s.size() && s[i] == '/') ++i;
  if (i < s.size() && s[i] == 'n' && !line.comment_first) {
    const int column = line.columns[i];
    std::size_t j = i + 1;
    while (j < s.size() && ((s[j] >= '0' && s[j] <= '9') || s[j] == '.')) ++j;
    if (j == i + 1) fail(column, "bad line number: N needs digits");
    i = j;
  }
  return i;
}

Block Interpreter::read_block(const CompactLine& line, std::size_t i) const {
  Block block;
  const std::string& s = line.code;
  while (i < s.size()) {
    const char c = s[i];
    const int column = line.columns[i];
    ++i;
    switch (c) {
      case 'g':
        read_g(line, i, column, block);
        continue;
      case 'm':
        read_m(line, i, column, block);
        continue;
      case 'x':
      case 'y':
      case 'z':
      case 'i':
      case 'j':
      case 'k':
      case 'r':
      case 'p':
      case 'q':
      case 'f':
      case 's':
      case 't':
      case 'h':
      case 'l':
      case 'd': {
        Word& word = block[c];
        const char upper = static_cast<char>(c - 'a' + 'A');
        if (word.present) fail(column, fmt::format("multiple {} words on one line", upper));
        const bool integer = c == 't' || c == 'h' || c == 'l';
        word.value = integer ? read_integer(line, i, column, c) : read_number(line, i, column, c);
        word.present = true;
        word.column = column;
        if (word.value < 0.0) {
          switch (c) {
            case 'f':
              fail(column, "negative F word used");
            case 's':
              fail(column, "negative spindle speed used");
            case 't':
              fail(column, "negative tool number used");
            case 'h':
              fail(column, "negative H word used");
            case 'l':
              fail(column, "negative L word used");
            default:
              break;
          }
        }
        continue;
      }
      case 'a':
      case 'b':
      case 'c':
        fail(column, fmt::format("rotary axis words (A, B, C) are not supported: {}",
                                 static_cast<char>(c - 'a' + 'A')));
      case 'u':
      case 'v':
      case 'w':
        fail(column, fmt::format("U, V and W axis words are not supported: {}",
                                 static_cast<char>(c - 'a' + 'A')));
      case 'e':
        fail(column, "E word is not supported");
      case 'o':
        fail(column, "an O-word must be the first word of its line");
      case '#':
        --i;
        block.settings.push_back(values(line).setting(i));
        continue;
      case '@':
      case '^': {
        Word& word = c == '@' ? block.polar_radius : block.polar_angle;
        if (word.present) fail(column, fmt::format("multiple {} words on one line", c));
        word.value = values(line).real(i);
        word.present = true;
        word.column = column;
        continue;
      }
      case '$':
        fail(column, "spindle selection ($) is not supported");
      case 'n':
        fail(column, "bad character 'N': a line number must be the first word of the line");
      default:
        fail(column,
             fmt::format("bad character {} used", describe_char(static_cast<unsigned char>(c))));
    }
  }
  return block;
}

bool Interpreter::next_line(std::string_view& raw) {
  const ProgramFile& file = *files_[static_cast<std::size_t>(at_.file)];
  const std::string_view text = file.text;
  if (at_.offset > text.size()) return false;
  if (file.mapped != nullptr) file.mapped->release_before(at_.offset);
  std::size_t end = text.find('\n', at_.offset);
  if (end == std::string_view::npos) end = text.size();
  raw = text.substr(at_.offset, end - at_.offset);
  if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
  line_offset_ = at_.offset;
  at_.offset = end + 1;
  line_ = ++at_.line;
  here_.line = line_;
  return true;
}

void Interpreter::go_to(const Position& at) {
  at_ = at;
  source_ = files_[static_cast<std::size_t>(at.file)]->name;
  here_.source = source_;
}

void Interpreter::end_of_file() {
  if (!skipping_to_sub_.empty()) {  // a call found no definition: blame the call
    go_to(skipping_start_);
    line_ = skipping_start_.line;
    fail(0, fmt::format("subroutine o<{}> is not defined: not in the program, and no {}.ngc in "
                        "the program's folder or the subroutine path",
                        skipping_to_sub_, skipping_to_sub_));
  }
  if (frames_.size() > 1) {
    fail(0, fmt::format("the file ends inside subroutine o<{}>: 'o<{}> endsub' missing",
                        frames_.back().sub_name, frames_.back().sub_name));
  }
  if (!skipping_o_.empty() && !ended_) {
    line_ = skipping_start_.line;
    fail(0, defining_sub_
                ? fmt::format("'o<{}> sub' has no 'o<{}> endsub' before the end of the file",
                              skipping_o_, skipping_o_)
                : fmt::format("the file ends while skipping to the end of o-word {} from here",
                              skipping_o_));
  }
}

bool Interpreter::run_line(std::string_view raw) {
  const bool main = at_.file == 0;
  std::string bare;  // the line without blanks, to recognise '%'
  for (char c : raw) {
    if (c != ' ' && c != '\t') bare.push_back(c);
  }
  if (main && !bare.empty() && !ended_) last_content_line_ = line_;
  if (ended_) {
    if (!main) return false;
    if (!bare.empty() && bare != "%" && ignored_lines_++ == 0) first_ignored_ = line_;
    return true;
  }
  if (main && bare == "%" && !seen_content_) {
    percent_opened_ = true;  // the optional '%' opening the program
    seen_content_ = true;
    return true;
  }
  if (main && bare == "%" && percent_opened_) {
    ended_ = true;  // the closing '%': the rest of the file is ignored
    return true;
  }
  if (!bare.empty()) seen_content_ = true;
  const CompactLine line = compact(raw);
  if (line.code.empty()) return true;
  const std::size_t i = after_line_number(line);
  if (line.at(i) == 'o') {
    control(read_o(line, i));
  } else if (const std::optional<OLine> m = read_m98(line, i)) {
    control(*m);
  } else if (skipping_o_.empty()) {
    const Block block = read_block(line, i);
    if (!execute(block)) ended_ = true;
    publish_state();
  }
  return true;
}

Toolpath Interpreter::run() {
  // Every error in the program, not only the first: a line in error is dropped and reading goes
  // on with the next (as LinuxCNC's rs274 -n 0 does). The first kErrorsKept are reported, then a
  // count; reading stops at kErrorsRead (a line in error inside an endless loop).
  constexpr std::size_t kErrorsKept = 20, kErrorsRead = 1000;
  std::vector<InputError> errors;
  std::size_t more = 0;
  const auto record = [&](const InputError& e) {
    if (errors.size() < kErrorsKept) {
      errors.push_back(e);
    } else {
      ++more;
    }
    return errors.size() + more < kErrorsRead;
  };
  std::size_t lines_read = 0;
  for (;;) {
    std::string_view raw;
    if (options_.max_lines_read > 0 && ++lines_read > options_.max_lines_read) {
      record(InputError(SourceLocation{source_, line_, 0},
                        fmt::format("reading stopped after {} lines (the reading's line limit)",
                                    options_.max_lines_read)));
      break;
    }
    if (!next_line(raw)) {
      try {
        end_of_file();
      } catch (const InputError& e) {
        record(e);
      }
      break;
    }
    try {
      if (!run_line(raw)) break;
    } catch (const InputError& e) {
      // A loop found never ending is the last error: reading on would only go round it again.
      if (never_ends_) {
        record(e);
        break;
      }
      if (!record(e)) {
        errors.push_back(
            InputError(e.location(), fmt::format("reading stopped after {} errors", kErrorsRead)));
        break;
      }
    }
  }
  if (!errors.empty()) {
    if (errors.size() == 1 && more == 0) throw errors.front();
    throw InputErrors(std::move(errors), more);
  }
  if (!seen_content_) {
    throw InputError(SourceLocation{source_, 0, 0}, "empty program: no G-code in the file");
  }
  closing_ = true;
  if (warnings_dropped_ > 0) {
    warn(line_, 0, fmt::format("… and {} more warnings", warnings_dropped_));
  }
  for (const Unmodelled& u : unmodelled_) {
    result_.warnings.push_back(
        {u.first, fmt::format("{} ({} line{})", u.what, u.lines, u.lines == 1 ? "" : "s")});
  }
  if (compensation_.held() > 0) {
    // LinuxCNC drops them too: only G40, M0, M1, M2 and M30 release held moves.
    warn(compensation_.first_held_line(), 0,
         fmt::format("the program ends with cutter radius compensation on: the {} compensated "
                     "move(s) held from here on are never made, as in LinuxCNC (end compensation "
                     "with G40, or the program with M2 or M30)",
                     compensation_.held()));
  }
  if (!ended_) {
    // LinuxCNC refuses such a file at its end; the path is complete, so cwe only warns.
    warn(last_content_line_, 0,
         percent_opened_ ? "file ended with no closing percent sign (the program is read to the "
                           "end)"
                         : "file ended with no program end (M2, M30) or percent sign (the "
                           "program is read to the end)");
  }
  if (ignored_lines_ > 0) {
    warn(first_ignored_, 0,
         fmt::format("{} line{} after the program end ignored, as LinuxCNC does", ignored_lines_,
                     ignored_lines_ == 1 ? "" : "s"));
  }
  return std::move(result_);
}

}  // namespace gcode

std::vector<std::string> parse_search_path(std::string_view text) {
  std::vector<std::string> folders;
  while (!text.empty()) {
    const std::size_t colon = text.find(':');
    const std::string_view folder = text.substr(0, colon);
    if (!folder.empty()) folders.emplace_back(folder);
    if (colon == std::string_view::npos) break;
    text.remove_prefix(colon + 1);
  }
  return folders;
}

Toolpath read_gcode(std::string_view text, const std::string& source, const GcodeOptions& options) {
  return gcode::Interpreter(text, source, options).run();
}

Toolpath read_gcode(std::string_view text, const std::string& source, const GcodeOptions& options,
                    const MoveSink& sink) {
  return gcode::Interpreter(text, source, options, &sink).run();
}

Toolpath read_gcode_file(const std::string& path, const GcodeOptions& options) {
  MappedText file(path, "G-code file");
  return gcode::Interpreter(file.text(), path, options, nullptr, &file).run();
}

Toolpath read_gcode_file(const std::string& path, const GcodeOptions& options,
                         const MoveSink& sink) {
  MappedText file(path, "G-code file");
  return gcode::Interpreter(file.text(), path, options, &sink, &file).run();
}

}  // namespace cwe
