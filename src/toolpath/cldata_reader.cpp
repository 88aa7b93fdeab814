#include "cwe/toolpath/cldata_reader.hpp"

// Source-form APT CLDATA, as Siemens NX (CLSF), CATIA V5, PTC Creo and Mastercam write it.
// docs/cldata.md lists every record, the conventions chosen and their references.
//
// Reading happens in two layers: a Lexer turns the text into records (continuation lines joined,
// comments dropped, the source position of every field kept), and a Reader interprets them one
// by one, keeping the machine state (position, axis, feed, spindle, tool) and appending moves.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/tool/apt.hpp"

namespace cwe {
namespace {

constexpr double kMillimetresPerFoot = 304.8;

// Most turns one CIRCLE/…,TIMES,n may add; no real helix comes near, and it bounds the work of
// whoever samples the arc.
constexpr int kMostTurns = 10000;

// ------------------------------------------------------------------------------------------------
// Lexing.

struct Position {
  int line = 0;
  int column = 0;
};

// One comma-separated field after the slash, trimmed and upper-cased, with where it starts (for
// an empty field: just after the separator before it).
struct Field {
  std::string text;
  Position where;
};

struct Record {
  std::string major;  // upper case, blanks collapsed; empty for a line of bare numbers
  Position where;     // of the major word (or of the first number)
  bool has_slash = false;
  std::vector<Field> fields;
  std::string literal;  // PARTNO, PPRINT, INSERT, TPRINT: the rest of the line as written
  // A problem found while joining the record's lines, reported if the record is interpreted.
  std::optional<std::pair<Position, std::string>> problem;
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char to_upper(char c) { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); }
bool starts_number(char c) { return is_digit(c) || c == '+' || c == '-' || c == '.'; }

// Text for a message: at most 40 characters, bytes that are not printable ASCII as \xNN.
std::string printable(std::string_view text) {
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += (c >= 0x20 && c < 0x7f) ? std::string(1, static_cast<char>(c))
                                   : fmt::format("\\x{:02X}", static_cast<unsigned>(c));
  }
  if (text.size() > 40) out += "…";
  return out;
}

// Records whose rest of line is free text (APT "literal" records): no fields, no `$` handling.
constexpr std::string_view kLiteralWords[] = {"PARTNO", "PPRINT", "INSERT", "TPRINT"};

class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte-order mark
  }

  // The next record, or nullopt at the end of the text.
  std::optional<Record> next() {
    Record record;
    std::string text;  // the record's characters, upper case, continuation lines joined by ' '
    std::vector<Position> where;  // source position of each character of `text`
    bool started = false;
    bool continued = false;
    std::string_view line;
    while (read_line(line)) {
      const int number = line_number_;
      std::size_t i = 0;
      if (!started) {
        while (i < line.size() && is_blank(line[i])) ++i;
        if (i == line.size() || line.substr(i, 2) == "$$") continue;  // blank or comment line
        if (std::optional<Record> literal = literal_record(line, i, number)) return literal;
      }
      bool content = false;
      bool continues = false;
      for (; i < line.size(); ++i) {
        const char c = line[i];
        if (c == '$') {
          if (i + 1 < line.size() && line[i + 1] == '$') break;  // comment to the end of the line
          // A single `$` continues the record on the next line; only blanks or a `$$` comment
          // may follow it.
          continues = true;
          std::size_t k = i + 1;
          while (k < line.size() && is_blank(line[k])) ++k;
          if (k < line.size() && line.substr(k, 2) != "$$" && !record.problem) {
            record.problem = {{number, static_cast<int>(k) + 1},
                              "unexpected text after the continuation mark '$' (a comment "
                              "starts with '$$')"};
          }
          break;
        }
        if (!is_blank(c)) content = true;
        text.push_back(to_upper(c));
        where.push_back({number, static_cast<int>(i) + 1});
      }
      if (continues) {
        started = continued = true;
        text.push_back(' ');
        where.push_back({number, static_cast<int>(line.size()) + 1});
        continue;
      }
      if (!content) {
        if (continued) continue;  // a blank or comment line inside a continued record
        text.clear();
        where.clear();
        continue;
      }
      return make_record(std::move(record), text, where);
    }
    if (!started) return std::nullopt;
    // The text ended inside a record continued with `$`.
    Record out = make_record(std::move(record), text, where);
    if (!out.problem) {
      out.problem = {out.where,
                     "the record is continued with '$' but the file ends before its next line"};
    }
    return out;
  }

 private:
  bool read_line(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = pos_;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    line = text_.substr(pos_, end - pos_);
    pos_ = end;
    if (pos_ < text_.size() && text_[pos_] == '\r') ++pos_;  // CR LF, or a lone CR
    if (pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
    ++line_number_;
    return true;
  }

  // PARTNO, PPRINT, INSERT, TPRINT: the text after the word (and an optional slash) as written.
  static std::optional<Record> literal_record(std::string_view line, std::size_t i, int number) {
    std::size_t end = i;
    while (end < line.size() && is_letter(line[end])) ++end;
    std::string word;
    for (std::size_t k = i; k < end; ++k) word += to_upper(line[k]);
    if (std::find(std::begin(kLiteralWords), std::end(kLiteralWords), word) ==
        std::end(kLiteralWords)) {
      return std::nullopt;
    }
    if (end < line.size() && !is_blank(line[end]) && line[end] != '/') return std::nullopt;
    std::size_t k = end;
    while (k < line.size() && is_blank(line[k])) ++k;
    if (k < line.size() && line[k] == '/') ++k;
    while (k < line.size() && is_blank(line[k])) ++k;
    std::size_t stop = line.size();
    while (stop > k && is_blank(line[stop - 1])) --stop;
    Record record;
    record.major = word;
    record.where = {number, static_cast<int>(i) + 1};
    record.literal = std::string(line.substr(k, stop - k));
    return record;
  }

  static Record make_record(Record record, const std::string& text,
                            const std::vector<Position>& where) {
    std::size_t first = 0;
    while (first < text.size() && is_blank(text[first])) ++first;
    if (first == text.size()) {
      record.where = where.empty() ? Position{} : where.front();
      return record;
    }
    record.where = where[first];
    const std::size_t slash = text.find('/', first);
    std::size_t fields_from = std::string::npos;
    std::size_t major_end = text.size();
    if (slash != std::string::npos) {
      record.has_slash = true;
      major_end = slash;
      fields_from = slash + 1;
    } else if (starts_number(text[first])) {
      major_end = first;  // bare numbers: the points that continue a GOTO
      fields_from = first;
    }
    // The major word with runs of blanks collapsed ("TOOL PATH", "GOTO  " → "GOTO").
    for (std::size_t k = first; k < major_end; ++k) {
      if (!is_blank(text[k])) {
        if (k > first && is_blank(text[k - 1]) && !record.major.empty()) record.major += ' ';
        record.major += text[k];
      }
    }
    if (fields_from == std::string::npos) return record;
    const Position after_end = {where.back().line, where.back().column + 1};
    std::size_t begin = fields_from;
    while (true) {
      const std::size_t comma = text.find(',', begin);
      const std::size_t end = comma == std::string::npos ? text.size() : comma;
      std::size_t b = begin;
      std::size_t e = end;
      while (b < e && is_blank(text[b])) ++b;
      while (e > b && is_blank(text[e - 1])) --e;
      Field field;
      field.text = text.substr(b, e - b);
      field.where = b < e ? where[b] : (begin < where.size() ? where[begin] : after_end);
      record.fields.push_back(std::move(field));
      if (comma == std::string::npos) break;
      begin = comma + 1;
    }
    return record;
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  int line_number_ = 0;
};

// Does the program hold NX CLSF "TOOL PATH/" records (NX writes one at the start of every
// operation)? NX's CIRCLE axis has the opposite sense (docs/cldata.md), so this must be known
// before the first CIRCLE.
bool is_nx_clsf(std::string_view text) {
  constexpr std::string_view kWord = "TOOL PATH";
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::size_t i = pos;
    while (i < end && is_blank(text[i])) ++i;
    std::size_t k = 0;
    while (k < kWord.size() && i + k < end && to_upper(text[i + k]) == kWord[k]) ++k;
    if (k == kWord.size()) {
      std::size_t j = i + k;
      while (j < end && is_blank(text[j])) ++j;
      if (j < end && text[j] == '/') return true;
    }
    pos = end + 1;
  }
  return false;
}

enum class NumberStatus { kOk, kMalformed, kOutOfRange };

// APT numbers: an optional sign, digits with an optional decimal point (1., .5, 12), an optional
// exponent E±n. `text` is upper case.
NumberStatus parse_number(std::string_view text, double& value) {
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) negative = text[i++] == '-';
  const std::size_t mantissa = i;
  int digits = 0;
  while (i < text.size() && is_digit(text[i])) ++i, ++digits;
  if (i < text.size() && text[i] == '.') {
    ++i;
    while (i < text.size() && is_digit(text[i])) ++i, ++digits;
  }
  if (digits == 0) return NumberStatus::kMalformed;
  if (i < text.size() && text[i] == 'E') {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    int exponent_digits = 0;
    while (i < text.size() && is_digit(text[i])) ++i, ++exponent_digits;
    if (exponent_digits == 0) return NumberStatus::kMalformed;
  }
  if (i != text.size()) return NumberStatus::kMalformed;
  double magnitude = 0.0;
  const char* last = text.data() + text.size();
  const auto [end, error] = std::from_chars(text.data() + mantissa, last, magnitude);
  if (error == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (error != std::errc() || end != last) return NumberStatus::kMalformed;
  if (!(magnitude <= kLargestInputValue)) return NumberStatus::kOutOfRange;
  value = negative ? -magnitude : magnitude;
  return NumberStatus::kOk;
}

bool is_numeric(const Field& field) { return !field.text.empty() && starts_number(field.text[0]); }

// A major word: a letter, then letters, digits, '_', '-' and single blanks ("TOOL PATH").
bool is_major_word(std::string_view word) {
  if (word.empty() || !is_letter(word[0])) return false;
  return std::all_of(word.begin(), word.end(), [](char c) {
    return is_letter(c) || is_digit(c) || c == '_' || c == '-' || c == ' ';
  });
}

// Records accepted without effect on the moves (docs/cldata.md explains each).
constexpr std::string_view kIgnoredWords[] = {
    "PARTNO", "PPRINT", "INSERT", "TPRINT", "COOLNT", "INTOL",     "OUTTOL",
    "TOLER",  "SELECT", "OPSKIP", "OPSTOP", "END",    "STOP",      "DISPLY",
    "CLRSRF", "SET",    "MACHIN", "DELAY",  "PAINT",  "TOOL PATH", "END-OF-PATH"};

bool is_ignored_word(std::string_view word) {
  return std::find(std::begin(kIgnoredWords), std::end(kIgnoredWords), word) !=
         std::end(kIgnoredWords);
}

// ------------------------------------------------------------------------------------------------
// Interpretation.

class Reader {
 public:
  Reader(std::string source, bool nx_clsf, const Vec3& start)
      : source_(std::move(source)), nx_clsf_(nx_clsf), position_(start) {
    path_.sources = {source_};
  }

  // Interprets one record; false once FINI has ended the program.
  bool read(const Record& record) {
    if (record.problem) fail(record.problem->first, record.problem->second);
    ++records_;
    // Points on lines of their own continue the GOTO just before them (Creo writes arcs so).
    const bool after_goto = goto_continues_;
    std::optional<Circle> goto_circle = std::move(goto_circle_);
    goto_continues_ = false;
    goto_circle_.reset();

    const std::string& word = record.major;
    if (word.empty() && record.has_slash) fail(record.where, "expected a major word before '/'");
    if (word.empty()) {
      continue_goto(record, after_goto, goto_circle);
      return true;
    }
    if (!is_major_word(word)) {
      fail(record.where,
           fmt::format("expected a record such as GOTO/x,y,z, found '{}'", printable(word)));
    }
    if (circle_ && (word == "GODLTA" || word == "FROM" || word == "CIRCLE")) {
      fail(record.where, fmt::format("{} follows the CIRCLE at line {}, which must be followed by "
                                     "the GOTO that ends the arc",
                                     word, circle_->where.line));
    }
    if (word == "GOTO") {
      go_to(record);
    } else if (word == "RAPID") {
      require_no_values(record, "RAPID");
      rapid_next_ = true;
    } else if (word == "FEDRAT") {
      feed_rate(record);
    } else if (word == "GODLTA") {
      go_delta(record);
    } else if (word == "CIRCLE") {
      circle(record);
    } else if (word == "FROM") {
      from(record);
    } else if (word == "TLAXIS") {
      const std::vector<double> v = numbers(record, 3, 3, "TLAXIS takes i,j,k");
      axis_ = direction(v[0], v[1], v[2], record.fields[0].where);
      axis_stated_ = true;
    } else if (word == "MULTAX") {
      multax(record);
    } else if (word == "SPINDL") {
      spindle(record);
    } else if (word == "UNITS") {
      units(record);
    } else if (word == "CUTTER") {
      cutter(record);
    } else if (word == "LOADTL") {
      load_tool(record, 0, "LOADTL takes the tool number, LOADTL/n");
    } else if (word == "LOAD") {
      if (record.fields.empty() || record.fields[0].text != "TOOL") {
        warn(record.where, "LOAD/ without TOOL ignored");
      } else {
        load_tool(record, 1, "LOAD/TOOL takes the tool number, LOAD/TOOL,n");
      }
    } else if (word == "CUTCOM") {
      if (record.fields.empty() || record.fields[0].text != "OFF") {
        warn(record.where,
             "CUTCOM: cutter compensation is not applied; the path is read as "
             "written (the tool tip)");
      }
    } else if (word == "CYCLE") {
      if (record.fields.empty() || record.fields[0].text != "OFF") {
        warn(record.where,
             fmt::format("CYCLE/{}: canned cycles are not expanded; the GOTOs that "
                         "follow are read as plain moves (no drilling strokes)",
                         record.fields.empty() ? "" : printable(record.fields[0].text)));
      }
    } else if (word == "MSYS") {
      machine_system(record);
    } else if (word == "TLDATA") {
      warn(record.where,
           "TLDATA (NX tool data) is not read: give the tool as CUTTER/ or on the "
           "command line");
    } else if (word == "FINI") {
      return false;
    } else if (!is_ignored_word(word)) {
      if (unknown_++ == 0) first_unknown_ = {record.where, word};
      warn(record.where, fmt::format("unknown record {} ignored", word));
    }
    return true;
  }

  void records_after_fini(Position first, int count) {
    warn(first, fmt::format("{} record{} after FINI ignored", count, count == 1 ? "" : "s"));
  }

  Toolpath finish() {
    if (circle_) fail(circle_->where, "CIRCLE is not followed by the GOTO that ends the arc");
    if (records_ > 0 && unknown_ == records_) {
      // Not one record known: not CLDATA (a G-code program saved as .cl, say).
      fail(first_unknown_.first,
           fmt::format("no record of this file is CLDATA (the first is '{}'): expected records "
                       "such as GOTO/x,y,z; a G-code program needs a G-code extension (.ngc, "
                       ".nc, .tap)",
                       printable(first_unknown_.second)));
    }
    settle_pending_cutter();
    return std::move(path_);
  }

 private:
  // A CIRCLE record waiting for (or being continued by) the GOTO that ends the arc. `normal` is
  // unit, with travel counter-clockwise about it (already reversed for NX CLSF).
  struct Circle {
    Vec3 center = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
    double radius = 0.0;
    int extra_turns = 0;
    Position where;
  };

  struct PendingCutter {
    AptCutter apt;
    Position where;
  };

  SourceLocation at(Position p) const { return {source_, p.line, p.column}; }
  [[noreturn]] void fail(Position p, const std::string& message) const {
    throw InputError(at(p), message);
  }
  void warn(Position p, std::string message) {
    path_.warnings.push_back({at(p), std::move(message)});
  }

  // CAM systems round to a number of decimals of the program's unit, so the tolerance for
  // written dimensions scales with the unit (mm).
  double length_tolerance() const { return tol::kInputLength * scale_; }

  double number(const Field& field) const {
    double value = 0.0;
    switch (parse_number(field.text, value)) {
      case NumberStatus::kOk:
        return value;
      case NumberStatus::kOutOfRange:
        fail(field.where, fmt::format("'{}' is out of range (numbers up to {:g} in magnitude "
                                      "are accepted)",
                                      printable(field.text), kLargestInputValue));
      case NumberStatus::kMalformed:
        break;
    }
    if (field.text.empty()) fail(field.where, "expected a number");
    fail(field.where, fmt::format("expected a number, found '{}'", printable(field.text)));
  }

  // All fields as numbers, between `least` and `most` of them; `form` says what was expected.
  std::vector<double> numbers(const Record& record, std::size_t least, std::size_t most,
                              const char* form) const {
    if (!record.has_slash && record.major != "") fail(record.where, form);
    std::vector<double> values;
    values.reserve(record.fields.size());
    for (const Field& field : record.fields) {
      if (!is_numeric(field) && !field.text.empty()) {
        fail(field.where,
             fmt::format("{}: expected a number, found '{}'", form, printable(field.text)));
      }
      values.push_back(number(field));
    }
    if (values.size() < least || values.size() > most) {
      fail(record.where, fmt::format("{} ({} value{} given)", form, values.size(),
                                     values.size() == 1 ? "" : "s"));
    }
    return values;
  }

  // `form`, and what was found instead when there was something.
  [[noreturn]] void unexpected(const Field& field, const char* form) const {
    if (field.text.empty()) fail(field.where, form);
    fail(field.where, fmt::format("{}; found '{}'", form, printable(field.text)));
  }

  static bool has_values(const Record& record) {
    return !(record.fields.empty() || (record.fields.size() == 1 && record.fields[0].text.empty()));
  }

  void require_no_values(const Record& record, const char* word) const {
    if (has_values(record)) fail(record.fields[0].where, fmt::format("{} takes no values", word));
  }

  // A unit vector from the written components.
  Vec3 direction(double i, double j, double k, Position where) const {
    const Vec3 v(i, j, k);
    const double length = v.norm();
    if (!(length >= tol::kInputDirection)) {
      fail(where, fmt::format("({:g}, {:g}, {:g}) is not a direction: its length is {:g}", i, j, k,
                              length));
    }
    return v / length;
  }

  int whole_number(const Field& field, int least, int most, const char* what) const {
    const double value = number(field);
    if (value != std::floor(value) || value < least || value > most) {
      fail(field.where, fmt::format("{}: expected a whole number from {} to {}, found '{}'", what,
                                    least, most, printable(field.text)));
    }
    return static_cast<int>(value);
  }

  // ---- state changes

  void units(const Record& record) {
    const std::string unit = record.fields.size() == 1 ? record.fields[0].text : "";
    if (unit == "MM") {
      scale_ = 1.0;
      path_.units = ProgramUnits::kMillimetres;
    } else if (unit == "INCHES" || unit == "INCH") {
      scale_ = kMillimetresPerInch;
      path_.units = ProgramUnits::kInches;
    } else {
      fail(record.fields.empty() ? record.where : record.fields[0].where,
           "UNITS takes MM or INCHES");
    }
  }

  void multax(const Record& record) {
    const std::string value = has_values(record) ? record.fields[0].text : "ON";
    if (record.fields.size() > 1 || (value != "ON" && value != "OFF")) {
      fail(record.fields[0].where, "MULTAX takes ON or OFF");
    }
    multax_ = value == "ON";
  }

  // FEDRAT/f, FEDRAT/f,unit and FEDRAT/unit,f (both orders are written).
  void feed_rate(const Record& record) {
    constexpr const char* kForm =
        "FEDRAT takes a feed and an optional unit (MMPM, IPM, PERMIN, "
        "MMPR, IPR, PERREV)";
    std::optional<double> value;
    std::string unit;
    for (const Field& field : record.fields) {
      if (is_numeric(field) && !value) {
        value = number(field);
        if (*value < 0.0) fail(field.where, "the feed rate cannot be negative");
      } else if (!is_numeric(field) && unit.empty() &&
                 (field.text == "MMPM" || field.text == "IPM" || field.text == "PERMIN" ||
                  field.text == "MMPR" || field.text == "IPR" || field.text == "PERREV")) {
        unit = field.text;
      } else {
        unexpected(field, kForm);
      }
    }
    if (!value) fail(record.where, kForm);
    feed_per_revolution_ = unit == "MMPR" || unit == "IPR" || unit == "PERREV";
    const double factor = unit == "MMPM" || unit == "MMPR" ? 1.0
                          : unit == "IPM" || unit == "IPR" ? kMillimetresPerInch
                                                           : scale_;
    feed_ = *value * factor;
    feed_known_ = true;
    warned_feed_per_revolution_ = false;
    rapid_next_ = false;  // a programmed feed replaces a pending RAPID
  }

  // SPINDL/n[,CLW|CCLW][,RPM|SFM|SMM] in any order, SPINDL/OFF, SPINDL/ON.
  void spindle(const Record& record) {
    constexpr const char* kForm =
        "SPINDL takes a speed with CLW or CCLW and RPM, SFM or SMM, or ON, or OFF";
    if (!has_values(record)) fail(record.where, kForm);
    if (record.fields.size() == 1 && record.fields[0].text == "OFF") {
      spindle_speed_ = 0.0;
      spindle_ = SpindleDirection::kStopped;
      return;
    }
    if (record.fields.size() == 1 && record.fields[0].text == "ON") {
      spindle_speed_ = last_speed_;
      spindle_ = last_speed_ > 0.0 ? last_direction_ : SpindleDirection::kStopped;
      warned_feed_per_revolution_ = false;
      return;
    }
    std::optional<double> speed;
    std::optional<SpindleDirection> direction;
    std::string unit;
    for (std::size_t i = 0; i < record.fields.size(); ++i) {
      const Field& field = record.fields[i];
      if (is_numeric(field) && !speed) {
        speed = number(field);
        if (*speed < 0.0) fail(field.where, "the spindle speed cannot be negative");
      } else if ((field.text == "CLW" || field.text == "CCLW") && !direction) {
        direction = field.text == "CLW" ? SpindleDirection::kClockwise
                                        : SpindleDirection::kCounterClockwise;
      } else if ((field.text == "RPM" || field.text == "SFM" || field.text == "SMM") &&
                 unit.empty()) {
        unit = field.text;
      } else if ((field.text == "RANGE" || field.text == "MAXRPM") &&
                 i + 1 < record.fields.size() && is_numeric(record.fields[i + 1])) {
        number(record.fields[++i]);  // gear range, speed limit: no effect on the path
      } else {
        unexpected(field, kForm);
      }
    }
    if (!speed) fail(record.where, kForm);
    double rpm = *speed;
    if (unit == "SFM" || unit == "SMM") {
      // Surface speed: rev/min = v / (π d) with the current tool's diameter.
      const double diameter = current_diameter();
      if (diameter > 0.0) {
        rpm = *speed * (unit == "SMM" ? 1000.0 : kMillimetresPerFoot) / (kPi * diameter);
      } else {
        warn(record.where, fmt::format("SPINDL/{}: the surface speed cannot be converted without "
                                       "a CUTTER/ diameter; spindle speed read as 0",
                                       unit));
        rpm = 0.0;
      }
    }
    const SpindleDirection turning =
        direction.value_or(last_speed_ > 0.0 ? last_direction_ : SpindleDirection::kClockwise);
    spindle_speed_ = rpm;
    spindle_ = rpm > 0.0 ? turning : SpindleDirection::kStopped;
    if (rpm > 0.0) {
      last_speed_ = rpm;
      last_direction_ = turning;
    }
    warned_feed_per_revolution_ = false;
  }

  double current_diameter() const {
    if (pending_cutter_) return pending_cutter_->apt.d;
    const auto it = path_.tool_definitions.find(tool_);
    return it != path_.tool_definitions.end() ? it->second.d : 0.0;
  }

  // CUTTER/ names the tool being loaded (CATIA writes CUTTER/ before LOADTL/) or, just after a
  // LOADTL/, the tool loaded; otherwise the current tool, 0 when none was loaded.
  void cutter(const Record& record) {
    std::vector<double> v =
        numbers(record, 1, 7, "CUTTER takes 1 to 7 numbers, d[,r[,e,f[,alpha,beta[,h]]]]");
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i != 4 && i != 5) v[i] *= scale_;  // lengths; alpha and beta are degrees
    }
    const AptCutter apt = apt_from_values(v, at(record.where));
    if (tool_just_loaded_) {
      define_tool(tool_, apt, record.where);
      return;
    }
    if (pending_cutter_) {
      warn(record.where, fmt::format("CUTTER replaces the one at line {}, which no LOADTL or "
                                     "motion used",
                                     pending_cutter_->where.line));
    }
    pending_cutter_ = PendingCutter{apt, record.where};
  }

  void define_tool(int tool, const AptCutter& apt, Position where) {
    try {
      apt_profile(apt, at(where));
    } catch (const InputError& e) {
      warn(where, fmt::format("{} ignored: {} (tool {} stays undefined)", to_string(apt),
                              e.message(), tool));
      return;
    }
    const auto it = path_.tool_definitions.find(tool);
    if (it != path_.tool_definitions.end()) {
      const AptCutter& old = it->second;
      if (old.d != apt.d || old.r != apt.r || old.e != apt.e || old.f != apt.f ||
          old.alpha_deg != apt.alpha_deg || old.beta_deg != apt.beta_deg || old.h != apt.h) {
        warn(where, fmt::format("tool {} redefined: {} replaces {}", tool, to_string(apt),
                                to_string(old)));
      }
    }
    path_.tool_definitions[tool] = apt;
  }

  void settle_pending_cutter() {
    if (!pending_cutter_) return;
    define_tool(tool_, pending_cutter_->apt, pending_cutter_->where);
    pending_cutter_.reset();
  }

  void load_tool(const Record& record, std::size_t index, const char* form) {
    if (record.fields.size() <= index || !is_numeric(record.fields[index])) {
      fail(record.fields.size() > index ? record.fields[index].where : record.where, form);
    }
    tool_ =
        whole_number(record.fields[index], 0, static_cast<int>(kLargestInputValue), "tool number");
    path_.tool_changes.push_back({tool_, at(record.where)});
    if (pending_cutter_) {
      define_tool(tool_, pending_cutter_->apt, pending_cutter_->where);
      pending_cutter_.reset();
    }
    tool_just_loaded_ = true;
  }

  // NX's machine coordinate system. cwe reads positions as written (in the MCS); a system other
  // than the identity is reported.
  void machine_system(const Record& record) {
    constexpr double kIdentity[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bool identity = record.fields.size() == 9;
    for (std::size_t i = 0; identity && i < 9; ++i) {
      double value = 0.0;
      identity = parse_number(record.fields[i].text, value) == NumberStatus::kOk &&
                 std::abs(value - kIdentity[i]) <= tol::kInputLength;
    }
    if (!identity) {
      warn(record.where,
           "MSYS: positions are read in the machine coordinate system; its "
           "placement in the part is not applied");
    }
  }

  // ---- motion

  MotionMode take_rapid() {
    const MotionMode mode = rapid_next_ ? MotionMode::kRapid : MotionMode::kFeed;
    rapid_next_ = false;
    return mode;
  }

  // x,y,z or x,y,z,i,j,k from the fields starting at `first` (MULTAX/ON requires the axis).
  void point(const Record& record, const std::vector<double>& v, std::size_t first, Vec3& p,
             std::optional<Vec3>& axis) const {
    p = Vec3(v[first], v[first + 1], v[first + 2]) * scale_;
    if (v.size() - first == 6) {
      axis = direction(v[first + 3], v[first + 4], v[first + 5], record.fields[first + 3].where);
    }
  }

  void from(const Record& record) {
    const std::vector<double> v = numbers(record, 3, 6, "FROM takes x,y,z or x,y,z,i,j,k");
    if (v.size() != 3 && v.size() != 6) {
      fail(record.where,
           fmt::format("FROM takes x,y,z or x,y,z,i,j,k ({} values given)", v.size()));
    }
    std::optional<Vec3> axis;
    point(record, v, 0, position_, axis);
    if (axis) {
      axis_ = *axis;
      axis_stated_ = true;
    }
  }

  void go_to(const Record& record) {
    const MotionMode mode = take_rapid();
    add_point(record, mode, circle_);
    goto_mode_ = mode;
    goto_continues_ = true;
    if (circle_) {
      goto_circle_ = *circle_;
      goto_circle_->extra_turns = 0;  // TIMES,n belongs to the first piece only
      circle_.reset();
    }
  }

  void continue_goto(const Record& record, bool after_goto,
                     const std::optional<Circle>& goto_circle) {
    if (!after_goto) {
      fail(record.where,
           "numbers without a major word: only the points that continue a GOTO "
           "may stand alone on a line");
    }
    add_point(record, goto_mode_, goto_circle);
    goto_continues_ = true;
    goto_circle_ = goto_circle;
  }

  // One GOTO point: a line from the current position, or an arc on `circle`.
  void add_point(const Record& record, MotionMode mode, const std::optional<Circle>& circle) {
    const char* form =
        multax_ ? "GOTO takes x,y,z,i,j,k while MULTAX is on" : "GOTO takes x,y,z or x,y,z,i,j,k";
    const std::vector<double> v = numbers(record, multax_ ? 6 : 3, 6, form);
    if (v.size() != 6 && v.size() != 3) {
      fail(record.where, fmt::format("{} ({} values given)", form, v.size()));
    }
    Vec3 end;
    std::optional<Vec3> axis;
    point(record, v, 0, end, axis);
    // A program that states no axis before its first motion (FROM or TLAXIS with one) starts in
    // its first GOTO's orientation: no turn from an invented one.
    if (!axis_stated_ && axis) axis_ = *axis;
    if (circle) {
      add_arc(record, *circle, end, axis.value_or(axis_), mode);
    } else {
      add_line(record, end, axis.value_or(axis_), mode);
    }
  }

  void go_delta(const Record& record) {
    const std::vector<double> v =
        numbers(record, 1, 6, "GODLTA takes d (along the tool axis), dx,dy,dz or dx,dy,dz,i,j,k");
    Vec3 end = position_;
    std::optional<Vec3> axis;
    if (v.size() == 1) {
      end += v[0] * scale_ * axis_;
    } else if (v.size() == 3 || v.size() == 6) {
      Vec3 delta;
      point(record, v, 0, delta, axis);
      end += delta;
    } else {
      fail(record.where,
           fmt::format("GODLTA takes d, dx,dy,dz or dx,dy,dz,i,j,k ({} values given)", v.size()));
    }
    add_line(record, end, axis.value_or(axis_), take_rapid());
  }

  void circle(const Record& record) {
    constexpr const char* kForm = "CIRCLE takes xc,yc,zc,i,j,k,r and optional values";
    if (record.fields.size() < 7) {
      fail(record.fields.empty() ? record.where : record.fields.back().where,
           fmt::format("{} ({} given)", kForm, record.fields.size()));
    }
    double v[7];
    for (std::size_t i = 0; i < 7; ++i) v[i] = number(record.fields[i]);
    Circle c;
    c.where = record.where;
    c.center = Vec3(v[0], v[1], v[2]) * scale_;
    c.normal = direction(v[3], v[4], v[5], record.fields[3].where);
    // NX CLSF gives the axis about which travel is clockwise (docs/cldata.md).
    if (nx_clsf_) c.normal = -c.normal;
    c.radius = v[6] * scale_;
    if (!(c.radius > length_tolerance())) {
      fail(record.fields[6].where, fmt::format("the circle radius must be positive, found '{}'",
                                               printable(record.fields[6].text)));
    }
    // Extra values (NX: tolerance, ratio, tool diameter, corner radius) and TIMES,n (n turns).
    for (std::size_t i = 7; i < record.fields.size(); ++i) {
      const Field& field = record.fields[i];
      if (field.text == "TIMES" && i + 1 < record.fields.size()) {
        c.extra_turns = whole_number(record.fields[++i], 1, kMostTurns, "CIRCLE TIMES") - 1;
      } else if (is_numeric(field)) {
        number(field);
      } else {
        unexpected(field, kForm);
      }
    }
    circle_ = c;
  }

  // A move from the current position with the state every move carries.
  Move new_move(MotionMode mode, Position where) {
    settle_pending_cutter();
    axis_stated_ = true;
    tool_just_loaded_ = false;
    Move move;
    move.mode = mode;
    move.start = position_;
    move.start_axis = axis_;
    move.tool = tool_;
    move.spindle_speed = spindle_speed_;
    move.spindle = spindle_;
    move.line = where.line;
    move.source = 0;
    if (mode == MotionMode::kFeed) {
      if (!feed_known_ && !warned_no_feed_) {
        warn(where, "feed move before any FEDRAT: its feed rate is 0");
        warned_no_feed_ = true;
      }
      move.feed_rate = feed_;
      if (feed_per_revolution_) {
        move.feed_rate = feed_ * spindle_speed_;
        if (spindle_speed_ <= 0.0 && !warned_feed_per_revolution_) {
          warn(where, "feed per revolution with the spindle stopped: feed rate 0");
          warned_feed_per_revolution_ = true;
        }
      }
    }
    return move;
  }

  void add_line(const Record& record, const Vec3& end, const Vec3& end_axis, MotionMode mode) {
    Move move = new_move(mode, record.where);
    move.end = end;
    move.end_axis = end_axis;
    hold_move(path_.moves, move, at(record.where));
    position_ = end;
    axis_ = end_axis;
  }

  // The arc from the current position about `c` to `end`, counter-clockwise about c.normal; a
  // helix when `end` is offset along the normal. Both ends must lie on the circle within the
  // input tolerance; the centre is then moved onto the bisector of the chord (by at most that
  // tolerance's order) so that Move::position(1) is `end` up to rounding.
  void add_arc(const Record& record, const Circle& c, const Vec3& end, const Vec3& end_axis,
               MotionMode mode) {
    const double tolerance = length_tolerance();
    const Vec3& n = c.normal;
    const Vec3 start = position_;
    const Vec3 center = c.center + n * n.dot(start - c.center);  // at the start's height
    const double start_radius = (start - center).norm();
    if (std::abs(start_radius - c.radius) > tolerance) {
      fail(c.where,
           fmt::format("the arc starts at ({:.6g}, {:.6g}, {:.6g}) mm, {:.6g} mm from "
                       "the axis of this CIRCLE of radius {:.6g} mm (tolerance {:g} mm)",
                       start.x(), start.y(), start.z(), start_radius, c.radius, tolerance));
    }
    const double axial = n.dot(end - start);
    const Vec3 end_in_plane = end - axial * n;
    const double end_radius = (end_in_plane - center).norm();
    if (std::abs(end_radius - c.radius) > tolerance) {
      fail(record.where,
           fmt::format("the arc of the CIRCLE at line {} ends at ({:.6g}, {:.6g}, {:.6g}) mm, "
                       "{:.6g} mm from its axis, not on the circle of radius {:.6g} mm "
                       "(tolerance {:g} mm)",
                       c.where.line, end.x(), end.y(), end.z(), end_radius, c.radius, tolerance));
    }
    Move move = new_move(mode, record.where);
    move.shape = MoveShape::kArc;
    move.normal = n;
    move.axial = axial;
    move.end = end;
    move.end_axis = end_axis;
    const Vec3 chord = end_in_plane - start;
    const double chord_length = chord.norm();
    if (chord_length <= tolerance) {
      // Start and end coincide (in the plane): a full circle, as CAM systems write one.
      move.center = center;
      move.sweep = kTwoPi;
    } else {
      const Vec3 along = chord / chord_length;
      move.center = center + along * along.dot(0.5 * (start + end_in_plane) - center);
      const Vec3 a = start - move.center;
      const Vec3 b = end_in_plane - move.center;
      move.sweep = std::atan2(n.dot(a.cross(b)), a.dot(b));
      if (move.sweep <= 0.0) move.sweep += kTwoPi;  // counter-clockwise: (0, 2π)
    }
    move.sweep += kTwoPi * c.extra_turns;
    hold_move(path_.moves, move, at(record.where));
    position_ = end;
    axis_ = end_axis;
  }

  std::string source_;
  bool nx_clsf_ = false;
  Toolpath path_;
  std::size_t records_ = 0, unknown_ = 0;           // records read, and of them unknown
  std::pair<Position, std::string> first_unknown_;  // the first unknown record and its word

  double scale_ = 1.0;  // mm per program unit
  Vec3 position_ = Vec3::Zero();
  Vec3 axis_ = Vec3::UnitZ();
  bool axis_stated_ = false;  // by FROM, TLAXIS or a motion
  bool multax_ = false;
  bool rapid_next_ = false;

  double feed_ = 0.0;  // mm/min, or mm/rev when feed_per_revolution_
  bool feed_per_revolution_ = false;
  bool feed_known_ = false;
  bool warned_no_feed_ = false;
  bool warned_feed_per_revolution_ = false;

  double spindle_speed_ = 0.0;  // rev/min
  SpindleDirection spindle_ = SpindleDirection::kStopped;
  double last_speed_ = 0.0;  // for SPINDL/ON
  SpindleDirection last_direction_ = SpindleDirection::kClockwise;

  int tool_ = 0;
  bool tool_just_loaded_ = false;  // LOADTL seen, no motion since
  std::optional<PendingCutter> pending_cutter_;

  std::optional<Circle> circle_;  // CIRCLE waiting for its GOTO
  bool goto_continues_ = false;   // the last record was a GOTO (or one of its points)
  MotionMode goto_mode_ = MotionMode::kFeed;
  std::optional<Circle> goto_circle_;  // the circle that GOTO's further points follow
};

}  // namespace

Toolpath read_cldata(std::string_view text, const std::string& source, const Vec3& start) {
  Lexer lexer(text);
  Reader reader(source, is_nx_clsf(text), start);
  while (std::optional<Record> record = lexer.next()) {
    if (reader.read(*record)) continue;
    // FINI ends the program: what follows is counted, not interpreted.
    int after = 0;
    Position first;
    while (std::optional<Record> rest = lexer.next()) {
      if (after++ == 0) first = rest->where;
    }
    if (after > 0) reader.records_after_fini(first, after);
    break;
  }
  return reader.finish();
}

Toolpath read_cldata_file(const std::string& path, const Vec3& start) {
  return read_cldata(read_text_file(path, "CLDATA file"), path, start);
}

}  // namespace cwe
