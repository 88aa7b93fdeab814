// The G-code interpreter (gcode_interpreter.hpp): O-word subroutines, conditions and loops
// (LinuxCNC's interp_o_word.cc), subroutine files and Fanuc-style M98/M99.

#include "gcode_interpreter.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"
#include "gcode_tolerance.hpp"

namespace cwe::gcode {

const char* Interpreter::o_name(OType type) const {
  switch (type) {
    case OType::kNone:
      return "none";
    case OType::kSub:
      return "sub";
    case OType::kEndsub:
      return "endsub";
    case OType::kCall:
      return "call";
    case OType::kDo:
      return "do";
    case OType::kWhile:
      return "while";
    case OType::kRepeat:
      return "repeat";
    case OType::kIf:
      return "if";
    case OType::kElseif:
      return "elseif";
    case OType::kElse:
      return "else";
    case OType::kEndif:
      return "endif";
    case OType::kBreak:
      return "break";
    case OType::kContinue:
      return "continue";
    case OType::kEndwhile:
      return "endwhile";
    case OType::kEndrepeat:
      return "endrepeat";
    case OType::kFanuc:
      return "(Fanuc-style subprogram)";
    case OType::kM98:
      return "M98";
    case OType::kM99:
      return "M99";
    case OType::kReturn:
      break;
  }
  return "return";
}

Interpreter::OLine Interpreter::read_o(const CompactLine& line, std::size_t i) {
  OLine o;
  o.at = Position{at_.file, line_offset_, line_};
  const gcode::ValueReader values = this->values(line);
  const int o_column = line.column(i);
  ++i;  // the 'o'
  if (line.at(i) == '<') {
    o.label = values.name(i);
  } else {
    o.label = fmt::format("{}", values.integer(i));
  }
  static constexpr std::pair<std::string_view, OType> kKeywords[] = {
      {"sub", OType::kSub},
      {"endsub", OType::kEndsub},
      {"call", OType::kCall},
      {"do", OType::kDo},
      {"while", OType::kWhile},
      {"repeat", OType::kRepeat},
      {"if", OType::kIf},
      {"elseif", OType::kElseif},
      {"else", OType::kElse},
      {"endif", OType::kEndif},
      {"break", OType::kBreak},
      {"continue", OType::kContinue},
      {"endwhile", OType::kEndwhile},
      {"endrepeat", OType::kEndrepeat},
      {"return", OType::kReturn}};
  for (const auto& [word, type] : kKeywords) {  // LinuxCNC's order: "else" after "elseif"
    if (line.code.compare(i, word.size(), word) == 0) {
      o.type = type;
      i += word.size();
      break;
    }
  }
  if (o.type == OType::kNone) {
    if (line.at(i) == '\0') {
      // A bare O number: a Fanuc-style subprogram that M98 calls, or (run into) a program
      // number, as posts write "O1001" first: LinuxCNC runs on.
      o.type = OType::kFanuc;
      o.name = o.label;
      return o;
    }
    fail(line.column(i),
         "unknown O-word command: expected sub, endsub, call, do, while, repeat, "
         "if, elseif, else, endif, break, continue, endwhile, endrepeat or return");
  }
  // Subroutine names are global; other labels belong to the subroutine they are in.
  const bool global = o.type == OType::kSub || o.type == OType::kEndsub || o.type == OType::kCall ||
                      o.type == OType::kReturn;
  if (global) {
    o.name = o.label;
  } else {
    const std::string sub =
        frames_.size() > 1 ? frames_.back().sub_name : (defining_sub_ ? sub_name_ : std::string());
    o.name = sub + "#" + o.label;
  }
  const bool skipping_other = !skipping_o_.empty() && skipping_o_ != o.name;
  switch (o.type) {
    case OType::kSub:
      if (defining_sub_) fail(o_column, "nested subroutine definition");
      break;
    case OType::kEndsub:
    case OType::kReturn:
      if (skipping_other || (defining_sub_ && frames_.size() == 1)) return o;
      // An optional return value.
      value_returned_ = line.at(i) == '[';
      return_value_ = value_returned_ ? values.expression(i) : 0.0;
      break;
    case OType::kCall:
      if (!skipping_o_.empty()) {  // skipping never ends on a call: its arguments are not evaluated
        o.type = OType::kNone;
        return o;
      }
      while (line.at(i) == '[') {
        if (o.args.size() == kSubroutineArguments) {
          fail(line.column(i),
               fmt::format("more than {} subroutine arguments", kSubroutineArguments));
        }
        o.args.push_back(values.expression(i));
      }
      break;
    case OType::kWhile:
    case OType::kIf:
    case OType::kElseif:
    case OType::kRepeat:
      if (defining_sub_ || skipping_other) {
        if (defining_sub_) o.type = OType::kNone;  // expressions are not evaluated in a definition
        return o;
      }
      if (line.at(i) != '[') {
        fail(line.column(i),
             fmt::format("o{} {}: a bracketed expression must follow", o.label, o_name(o.type)));
      }
      o.test = values.expression(i);
      break;
    default:
      if (defining_sub_) o.type = OType::kNone;
      break;
  }
  if (!skipping_o_.empty()) return o;  // the rest of a skipped line is not looked at
  if (i < line.code.size()) fail(line.column(i), "unexpected character after O-word");
  return o;
}

// LinuxCNC's read_items: M98, and M99 inside a subprogram, first on their line, are O-words.
std::optional<Interpreter::OLine> Interpreter::read_m98(const CompactLine& line, std::size_t i) {
  if (line.at(i) != 'm') return std::nullopt;
  std::size_t j = i + 1;
  int number = 0;
  try {
    number = values(line).integer(j);
  } catch (const InputError&) {
    return std::nullopt;  // read_block reports it
  }
  if (number != 98 && !(number == 99 && frames_.size() > 1)) return std::nullopt;
  OLine o;
  o.at = Position{at_.file, line_offset_, line_};
  if (number == 99) {
    if (defining_sub_) fail(line.column(i), "found 'M99' instead of 'O endsub' after 'O sub'");
    o.type = OType::kM99;
    o.name = o.label = frames_.back().sub_name;
    return o;
  }
  o.type = OType::kM98;
  if (!skipping_o_.empty()) return o;  // not looked at while skipping
  const Block block = read_block(line, j);
  if (!block.has('p')) fail(line.column(i), "found 'M98' code with no P-word");
  const double p = block['p'].value;
  if (std::abs(p - std::round(p)) > tol::kGcodeIntegerWord) {
    fail(block['p'].column, fmt::format("non-integer value for integer: P{:g}", p));
  }
  o.name = o.label = fmt::format("{}", static_cast<long long>(std::llround(p)));
  if (block.has('l')) o.repeats = static_cast<int>(block['l'].value);
  return o;
}

void Interpreter::save_offset(const OLine& o) {
  const auto it = offsets_.find(o.name);
  if (it != offsets_.end()) {
    if (it->second.at.line == o.at.line && it->second.at.file == o.at.file) {
      fail(1, fmt::format("o{} {} found in an illegal location", o.label, o_name(o.type)));
    }
    fail(1, fmt::format("o{} is already defined at line {}", o.label, it->second.at.line));
  }
  offsets_[o.name] = OffsetEntry{o.type, o.at, -1};
}

Interpreter::OffsetEntry& Interpreter::find_offset(const OLine& o) {
  const auto it = offsets_.find(o.name);
  if (it == offsets_.end()) {
    fail(1, fmt::format("o{} {}: undefined O-word label", o.label, o_name(o.type)));
  }
  return it->second;
}

std::optional<std::string> Interpreter::find_subroutine_file(const std::string& name) const {
  // LinuxCNC opens <name>.ngc from its SUBROUTINE_PATH; cwe looks beside the main program, then
  // in the subroutine path.
  std::vector<std::filesystem::path> folders;
  folders.push_back(std::filesystem::path(files_.front()->name).parent_path());
  for (const std::string& folder : options_.subroutine_path) folders.emplace_back(folder);
  for (const std::filesystem::path& folder : folders) {
    const std::filesystem::path candidate = folder / (name + ".ngc");
    std::error_code error;
    // Anything by that name is the file LinuxCNC would open: a folder is then an error when it
    // is read ("the G-code subroutine file is a directory"), not "no such file".
    if (std::filesystem::exists(candidate, error)) return candidate.string();
  }
  return std::nullopt;
}

int Interpreter::file_of(const std::string& path) {
  for (std::size_t f = 0; f < files_.size(); ++f) {
    if (files_[f]->name == path) return static_cast<int>(f);
  }
  auto file = std::make_unique<ProgramFile>();
  file->name = path;
  file->owned = std::make_unique<MappedText>(path, "G-code subroutine file");
  file->mapped = file->owned.get();
  file->text = file->owned->text();
  files_.push_back(std::move(file));
  result_.sources.push_back(path);
  return static_cast<int>(files_.size() - 1);
}

void Interpreter::back_to(const OLine& o) {
  // A label seen before: go back to its line (it is read again). Otherwise a subroutine: from
  // its own file if there is one, else further down this file; skip to its 'sub' line.
  const auto it = offsets_.find(o.name);
  if (it != offsets_.end()) {
    if (++idle_iterations_ > options_.max_idle_iterations) {
      never_ends_ = true;
      fail(1, fmt::format("o{} {}: {} loop iterations and calls without a move: the program "
                          "never ends (LinuxCNC would run it forever)",
                          o.label, o_name(o.type), options_.max_idle_iterations));
    }
    Position at = it->second.at;
    at.line -= 1;  // the line is read again
    go_to(at);
    return;
  }
  // A name is a file name in the search folders, never a path (o</etc/x> would open /etc/x.ngc).
  if (o.name.find('/') != std::string::npos) {
    fail(1, fmt::format("subroutine name o<{}>: a name cannot hold '/'", o.name));
  }
  if (const std::optional<std::string> file = find_subroutine_file(o.name)) {
    go_to(Position{file_of(*file), 0, 0});
  }
  skipping_o_ = o.name;
  skipping_to_sub_ = o.name;
  skipping_start_ = o.at;
}

void Interpreter::call(const OLine& o) {
  if (static_cast<int>(frames_.size()) >= kMaxCallLevels) fail(1, "too many subroutine levels");
  Frame& caller = frames_.back();
  caller.return_to = at_;
  const bool m98 = o.type == OType::kM98;
  if (!m98) {
    for (std::size_t k = 0; k < kSubroutineArguments; ++k) {
      caller.saved[k] = parameters_.numbered(static_cast<int>(k + 1));
      parameters_.set_numbered(static_cast<int>(k + 1), k < o.args.size() ? o.args[k] : 0.0);
    }
  } else if (o.repeats > 0) {
    // M98 L: the return goes back to the M98 line itself until the repeats are done.
    if (caller.m98_loop == -1) caller.m98_loop = o.repeats;
    if (--caller.m98_loop > 0) {
      caller.return_to = Position{o.at.file, o.at.offset, o.at.line - 1};
    } else {
      caller.m98_loop = -1;
    }
  }
  Frame frame;
  frame.sub_name = o.name;
  frame.m98 = m98;
  frames_.push_back(frame);
  parameters_.push_locals();
  skipping_o_.clear();
  back_to(o);
}

void Interpreter::give_back(const OLine& o) {
  if (frames_.size() == 1 && sub_name_.empty()) {
    fail(1, fmt::format("o{} {}: not in a subroutine definition", o.label, o_name(o.type)));
  }
  if (!skipping_o_.empty() && o.type == OType::kEndsub) skipping_o_.clear();
  if (frames_.size() > 1) {
    // Back to the caller: its #1-#30, its local parameters, its place; the state saved by an
    // M73 in the subroutine.
    const std::optional<ModalState> restored =
        frames_.back().restore_on_return ? frames_.back().state : std::nullopt;
    const bool m98 = frames_.back().m98;
    if (m98 != (o.type == OType::kM99)) {
      fail(1, m98 ? "Fanuc 'O....' subroutine definition must end with 'M99'"
                  : "'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine "
                    "definition");
    }
    frames_.pop_back();
    parameters_.pop_locals();
    const Frame& caller = frames_.back();
    if (!m98) {
      for (std::size_t k = 0; k < kSubroutineArguments; ++k) {
        parameters_.set_numbered(static_cast<int>(k + 1), caller.saved[k]);
      }
    }
    go_to(caller.return_to);
    sub_name_ = frames_.size() > 1 ? caller.sub_name : std::string();
    if (restored) restore(*restored);
    return;
  }
  if (o.type == OType::kEndsub) {  // the end of a definition at the main level
    if (!defining_sub_) fail(1, "not in a subroutine definition");
    skipping_o_.clear();
    defining_sub_ = false;
    sub_name_.clear();
  }
}

void Interpreter::control(const OLine& o) {
  if (!skipping_o_.empty() && skipping_o_ != o.name) return;
  if (!skipping_to_sub_.empty() && o.type != OType::kSub && o.type != OType::kFanuc) return;
  switch (o.type) {
    case OType::kNone:
      return;
    case OType::kFanuc:
      if (frames_.size() > 1 && !frames_.back().m98) {
        fail(1, "Fanuc 'O....' subroutine must be called with 'M98'");
      }
      if (!skipping_o_.empty()) {  // found the subprogram an M98 was looking for
        save_offset(o);
        skipping_o_.clear();
      }
      skipping_to_sub_.clear();
      return;  // run on, into it
    case OType::kM98:
      if (o.repeats == 0) return;  // L0: no call
      call(o);
      return;
    case OType::kM99:
      give_back(o);
      return;
    case OType::kSub:
      if (!skipping_o_.empty()) {  // found the sub a call was looking for
        save_offset(o);
        skipping_o_.clear();
      }
      skipping_to_sub_.clear();
      if (frames_.size() > 1 && frames_.back().m98) {
        fail(1, "'O.... sub' subroutine must be called with 'O.... call'");
      }
      if (frames_.size() > 1) return;  // a call: run its body
      // A definition: remember it and skip to its endsub.
      save_offset(o);
      skipping_o_ = o.name;
      skipping_start_ = o.at;
      defining_sub_ = true;
      sub_name_ = o.name;
      return;
    case OType::kEndsub:
    case OType::kReturn:
      give_back(o);
      return;
    case OType::kCall:
      call(o);
      return;
    case OType::kDo:
      skipping_o_.clear();
      if (offsets_.find(o.name) == offsets_.end()) save_offset(o);
      return;
    case OType::kRepeat: {
      const auto it = offsets_.find(o.name);
      if (it == offsets_.end()) {
        save_offset(o);
      } else if (it->second.at.line != o.at.line) {
        fail(1, fmt::format("o{} is already defined at line {}", o.label, it->second.at.line));
      }
      skipping_o_.clear();
      OffsetEntry& entry = offsets_[o.name];
      if (entry.repeat_count == -1) entry.repeat_count = static_cast<int>(std::lround(o.test));
      if (entry.repeat_count > 0) {
        --entry.repeat_count;
      } else {
        skipping_o_ = o.name;
        skipping_start_ = o.at;
        entry.repeat_count = -1;
      }
      return;
    }
    case OType::kWhile: {
      const auto it = offsets_.find(o.name);
      if (it != offsets_.end() && it->second.type != OType::kDo &&
          it->second.at.line != o.at.line) {
        fail(1, fmt::format("o{} is already defined at line {}", o.label, it->second.at.line));
      }
      if (it == offsets_.end()) save_offset(o);
      skipping_o_.clear();
      OffsetEntry& entry = offsets_[o.name];
      if (entry.type == OType::kWhile) {  // the start of a while loop
        if (o.test == 0.0) {
          skipping_o_ = o.name;
          skipping_start_ = o.at;
        }
      } else if (o.test != 0.0 && !doing_break_) {  // the end of a do loop
        back_to(o);
      } else {
        doing_break_ = false;
      }
      return;
    }
    case OType::kIf: {
      const auto it = offsets_.find(o.name);
      if (it == offsets_.end()) {
        save_offset(o);
      } else if (it->second.at.line != o.at.line) {
        fail(1, fmt::format("o{} is already defined at line {}", o.label, it->second.at.line));
      }
      executed_if_ = o.test != 0.0;
      if (executed_if_) {
        skipping_o_.clear();
      } else {
        skipping_o_ = o.name;
        skipping_start_ = o.at;
      }
      return;
    }
    case OType::kElseif:
    case OType::kElse:
    case OType::kEndif: {
      const OffsetEntry& entry = find_offset(o);
      if (entry.type != OType::kIf) {
        fail(1, fmt::format("o{} {}: no matching 'if' (o{} is a '{}' at line {})", o.label,
                            o_name(o.type), o.label, o_name(entry.type), entry.at.line));
      }
      if (o.type == OType::kEndif) {
        skipping_o_.clear();
        executed_if_ = true;
      } else if (executed_if_) {  // a branch already ran: skip the rest
        skipping_o_ = o.name;
        skipping_start_ = o.at;
      } else if (o.type == OType::kElse || o.test != 0.0) {
        skipping_o_.clear();
        executed_if_ = true;
      }
      return;
    }
    case OType::kBreak:
    case OType::kContinue: {
      const OffsetEntry& entry = find_offset(o);
      if (entry.type != OType::kWhile && entry.type != OType::kDo) {
        fail(1, fmt::format("o{} {}: no matching while or do (o{} is a '{}' at line {})", o.label,
                            o_name(o.type), o.label, o_name(entry.type), entry.at.line));
      }
      if (o.type == OType::kContinue && !skipping_o_.empty()) return;
      skipping_o_ = o.name;
      skipping_start_ = o.at;
      (o.type == OType::kBreak ? doing_break_ : doing_continue_) = true;
      return;
    }
    case OType::kEndwhile:
    case OType::kEndrepeat: {
      const OffsetEntry& entry = find_offset(o);
      const OType opening = o.type == OType::kEndwhile ? OType::kWhile : OType::kRepeat;
      if (entry.type != opening) {
        fail(1, fmt::format("o{} {}: no matching '{}' (o{} is a '{}' at line {})", o.label,
                            o_name(o.type), o_name(opening), o.label, o_name(entry.type),
                            entry.at.line));
      }
      if (!skipping_o_.empty()) {  // the loop is over, or a continue skipped here
        skipping_o_.clear();
        if (!doing_continue_) return;
        doing_continue_ = false;
      }
      back_to(o);
      return;
    }
  }
}

}  // namespace cwe::gcode
