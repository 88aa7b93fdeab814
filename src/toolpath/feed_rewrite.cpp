#include "cwe/toolpath/feed_rewrite.hpp"

// The program is read first with its own reader: that validates it (so the small lexers below
// only ever see text the readers accept) and tells which lines feed and at what feed. The lexers
// then mirror what the readers do with feeds and units, line by line; CWE_ASSERT checks that the
// original feed they track is the one the reader gave each feed line.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/toolpath/cldata_reader.hpp"

namespace cwe {
namespace {

// Decimals written for a feed: the program's own (the most any of its feeds has), at least
// kLeastDecimalsInch in inches (0.1 in/min), at most kMostDecimals*; kDefaultDecimals* for a
// program without feeds. More only when fewer would write 0.
constexpr int kMostDecimalsMm = 4;    // 1e-4 mm/min
constexpr int kMostDecimalsInch = 5;  // 1e-5 in/min, 2.5e-4 mm/min
constexpr int kLeastDecimalsInch = 1;
constexpr int kDefaultDecimalsMm = 1;
constexpr int kDefaultDecimalsInch = 2;

// Decimals of a number as written (digits after the point, before any exponent).
int decimals_of(std::string_view number) {
  const std::size_t point = number.find('.');
  if (point == std::string_view::npos) return 0;
  std::size_t end = point + 1;
  while (end < number.size() && number[end] >= '0' && number[end] <= '9') ++end;
  return static_cast<int>(end - point - 1);
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_upper(char c) { return c >= 'A' && c <= 'Z'; }
bool is_lower(char c) { return c >= 'a' && c <= 'z'; }
char to_upper(char c) { return is_lower(c) ? static_cast<char>(c - 'a' + 'A') : c; }
char to_lower(char c) { return is_upper(c) ? static_cast<char>(c - 'A' + 'a') : c; }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), to_lower);
  return s;
}

// An unsigned number (digits, a decimal point, an exponent for CLDATA) as the readers parse it:
// the nearest double.
double parse_unsigned(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  CWE_ASSERT(error == std::errc() && end == text.data() + text.size(),
             "a number the reader accepted parses");
  return value;
}

// A signed number: the readers refuse negative feeds, so the sign is at most '+'.
double parse_signed(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  return parse_unsigned(text);
}

// One change to the text: `length` bytes at `offset` of the original replaced by `text`
// (an insertion when `length` is 0).
struct Edit {
  std::size_t offset = 0;
  std::size_t length = 0;
  std::string text;
};

std::string apply_edits(std::string_view text, std::vector<Edit> edits) {
  std::stable_sort(edits.begin(), edits.end(),
                   [](const Edit& a, const Edit& b) { return a.offset < b.offset; });
  std::string out;
  std::size_t added = 0;
  for (const Edit& edit : edits) added += edit.text.size();
  out.reserve(text.size() + added);
  std::size_t position = 0;
  for (const Edit& edit : edits) {
    CWE_ASSERT(edit.offset >= position, "edits do not overlap");
    out.append(text.substr(position, edit.offset - position));
    out += edit.text;
    position = edit.offset + edit.length;
  }
  out.append(text.substr(position));
  return out;
}

// A feed as the program will state it: the text of the number and the feed the reader will make
// of it.
struct WrittenFeed {
  std::string text;
  double value = 0.0;  // in the reader's unit (mm/min, or mm/rev for CLDATA per revolution)
};

// `feed` (mm/min) in program units of `scale` mm, rounded to `decimals` decimals (more, up to
// `most`, when that would be 0), down when `down` (a scheduled feed is never written above the
// feed the schedule allows), else to the nearest, with no trailing zeros. Throws
// InputError at the line when the number would be 0 or out of range.
WrittenFeed write_feed(double feed, double scale, int decimals, int most, bool down,
                       const std::string& source, int line) {
  const double number = feed / scale;
  if (!(number <= kLargestInputValue)) {
    throw InputError(SourceLocation{source, line},
                     fmt::format("the feed rate {} mm/min is too large to write (more than {:g} "
                                 "program units)",
                                 feed, kLargestInputValue));
  }
  std::string text;
  double written = 0.0;
  for (int d = decimals; d <= std::max(decimals, most) && !(written > 0.0); ++d) {
    // Down, but not below a number within rounding of `number` (812.3 is 812.29999…).
    const double unit = std::pow(10.0, -d);
    const double rounded =
        down ? std::floor(number / unit * (1.0 + 1e-12)) * unit : number;
    text = fmt::format("{:.{}f}", rounded, d);
    if (text.find('.') != std::string::npos) {
      while (text.back() == '0') text.pop_back();
      if (text.back() == '.') text.pop_back();
    }
    written = parse_unsigned(text);
  }
  if (!(written > 0.0)) {
    throw InputError(SourceLocation{source, line},
                     fmt::format("the feed rate {} mm/min is 0 when written with {} decimals", feed,
                                 std::max(decimals, most)));
  }
  return {text, written * scale};
}

// Lines with at least one feed move, with the feed (mm/min) of the first, and a check of `feeds`.
struct FeedLines {
  std::map<int, double> feed;  // line → original feed of its first feed move
  int last = 0;                // the last feed line, 0 for none
};

FeedLines feed_lines(const Toolpath& path, const LineFeeds& feeds, const std::string& source) {
  FeedLines lines;
  for (const Move& move : path.moves) {
    if (move.is_rapid() || move.source != 0) continue;  // a subroutine file's lines are not ours
    lines.feed.emplace(move.line, move.feed_rate);
    lines.last = std::max(lines.last, move.line);
  }
  for (const auto& [line, feed] : feeds) {
    if (!(std::isfinite(feed) && feed > 0.0)) {
      throw InputError(SourceLocation{source, line},
                       fmt::format("expected a feed rate > 0 mm/min for line {}, found {}", line,
                                   feed));
    }
    if (lines.feed.count(line) == 0) {
      throw InputError(SourceLocation{source, line},
                       fmt::format("line {} has no feed move, so it cannot be given a feed rate",
                                   line));
    }
  }
  return lines;
}

// ---------------------------------------------------------------------------------------------
// G-code

// An F word: where its number is in the line and what it says.
struct FWord {
  std::size_t begin = 0, end = 0;  // byte range of the number (sign included) in the line
  std::string digits;              // the number without blanks or sign
  double value = 0.0;              // program units per minute
  int column = 0;                  // of the letter F, from 1
  bool interrupted = false;        // a comment inside the number (F1(…)00 is F100)
};

// A line of G-code as the reader's compact() and read_block() see it, for the words that matter
// here.
struct GcodeLine {
  std::size_t code_end = 0;    // byte offset just after the last character of a word
  bool has_code = false;       // any word at all
  bool packed = false;         // two or more words with no blank between any of them
  bool lower_case = false;     // its letters are all lower case
  std::optional<FWord> f;      // its F word
  std::optional<bool> inches;  // G20 (true) or G21 (false) on the line
};

GcodeLine lex_gcode_line(std::string_view raw, const std::string& source, int number) {
  GcodeLine out;
  std::string code;                  // comments and blanks removed, letters lowered
  std::vector<std::size_t> offsets;  // of each character of `code` in `raw`
  bool comment_first = false;
  bool blank_pending = false, blank_between = false;
  bool upper_seen = false, lower_seen = false;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const char c = raw[i];
    if (c == ' ' || c == '\t') {
      blank_pending = !code.empty();
      continue;
    }
    if (c == ';') break;
    if (c == '(') {
      if (code.empty()) comment_first = true;
      i = raw.find(')', i);  // the reader checked that it is closed
      CWE_ASSERT(i != std::string_view::npos, "comments are closed");
      continue;
    }
    if (blank_pending) blank_between = true;
    blank_pending = false;
    upper_seen = upper_seen || is_upper(c);
    lower_seen = lower_seen || is_lower(c);
    code.push_back(to_lower(c));
    offsets.push_back(i);
  }
  if (code.empty()) return out;
  out.has_code = true;
  out.code_end = offsets.back() + 1;
  out.lower_case = lower_seen && !upper_seen;

  const auto at_number = [&](std::size_t k) {
    return k < code.size() && (is_digit(code[k]) || code[k] == '.');
  };
  std::size_t k = 0;
  if (code[k] == '/') ++k;  // block delete
  if (k < code.size() && code[k] == 'n' && !comment_first) {
    ++k;
    while (at_number(k)) ++k;
  }
  int words = 0;
  while (k < code.size()) {
    const std::size_t letter = k++;
    ++words;
    const std::size_t begin = k;
    if (k < code.size() && (code[k] == '+' || code[k] == '-')) ++k;
    const std::size_t digits = k;
    while (at_number(k)) ++k;
    if (code[letter] == 'f') {
      const int column = static_cast<int>(offsets[letter]) + 1;
      if (k == digits) {
        // Unreachable for programs the reader accepts (it refuses # and [ everywhere); kept so
        // that no F word is ever skipped silently.
        throw InputError(SourceLocation{source, number, column},
                         "expected a number after F to rewrite the feed rate (F words with "
                         "parameters or expressions cannot be rewritten)");
      }
      FWord f;
      f.begin = offsets[begin];
      f.end = offsets[k - 1] + 1;
      f.digits = code.substr(digits, k - digits);
      f.value = parse_unsigned(f.digits);
      f.column = column;
      f.interrupted = raw.substr(f.begin, f.end - f.begin).find('(') != std::string_view::npos;
      out.f = f;
    } else if (code[letter] == 'g' && k > digits) {
      // The reader's rule: ten times the number, within a thousandth of an integer.
      const long tenths = std::lround(10.0 * parse_unsigned(code.substr(digits, k - digits)));
      if (tenths == 200) out.inches = true;
      if (tenths == 210) out.inches = false;
    }
  }
  out.packed = words >= 2 && !blank_between;
  return out;
}

std::string rewrite_gcode(std::string_view text, const LineFeeds& feeds, const std::string& source,
                          const GcodeOptions& options) {
  const FeedLines lines = feed_lines(read_gcode(text, source, options), feeds, source);
  if (feeds.empty()) return std::string(text);

  // The program's precision: the most decimals its F words have (up to its last feed move).
  std::optional<int> precision;
  for (std::size_t from = 0, number = 1;
       from < text.size() && number <= static_cast<std::size_t>(lines.last); ++number) {
    std::size_t to = text.find('\n', from);
    if (to == std::string_view::npos) to = text.size();
    std::string_view raw = text.substr(from, to - from);
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    from = to + 1;
    if (raw.find_first_not_of(" \t%") == std::string_view::npos) continue;
    const GcodeLine line = lex_gcode_line(raw, source, static_cast<int>(number));
    if (line.f) precision = std::max(precision.value_or(0), decimals_of(line.f->digits));
  }
  const int decimals_mm = std::min(precision.value_or(kDefaultDecimalsMm), kMostDecimalsMm);
  const int decimals_inch = std::clamp(precision.value_or(kDefaultDecimalsInch),
                                       kLeastDecimalsInch, kMostDecimalsInch);

  std::vector<Edit> edits;
  bool inches = options.initial_units == ProgramUnits::kInches;
  // The feed (mm/min) the original program has in force, and its F word.
  double original = 0.0;
  std::string original_digits;
  bool original_inches = false;
  // The feed the rewritten program has in force; `in_step`: the two programs agree from here on
  // (exactly, or as closely as a restoring F word in other units can say it).
  double output = 0.0;
  bool in_step = true;

  std::size_t begin = 0;
  for (int number = 1; number <= lines.last; ++number) {
    CWE_ASSERT(begin <= text.size(), "feed lines are lines of the text");
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(begin, end - begin);
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    const std::size_t line_begin = begin;
    begin = end + 1;
    // The '%' that opens the program (the closing one comes after the last move).
    if (raw.find_first_not_of(" \t") != std::string_view::npos &&
        raw.find_first_not_of(" \t%") == std::string_view::npos &&
        std::count(raw.begin(), raw.end(), '%') == 1) {
      continue;
    }
    const GcodeLine line = lex_gcode_line(raw, source, number);
    if (!line.has_code) continue;

    // F takes the units in force before the line's own G20/G21.
    const double scale = inches ? kMillimetresPerInch : 1.0;
    const int decimals = inches ? decimals_inch : decimals_mm;
    const int most = inches ? kMostDecimalsInch : kMostDecimalsMm;
    const auto listed = feeds.find(number);
    const bool feeds_here = lines.feed.count(number) > 0;
    const auto insert = [&](const std::string& digits) {
      std::string word = line.packed ? "" : " ";
      word += line.lower_case ? 'f' : 'F';
      edits.push_back({line_begin + line.code_end, 0, word + digits});
    };

    if (line.f) {
      original = line.f->value * scale;
      original_digits = line.f->digits;
      original_inches = inches;
      output = original;
      if (listed != feeds.end()) {
        const WrittenFeed written = write_feed(listed->second, scale, decimals, most, true, source, number);
        if (written.value != original) {
          if (line.f->interrupted) {
            throw InputError(SourceLocation{source, number, line.f->column},
                             "expected the number of the F word without a comment inside it, to "
                             "rewrite the feed rate");
          }
          edits.push_back({line_begin + line.f->begin, line.f->end - line.f->begin, written.text});
          output = written.value;
        }
      }
      in_step = output == original;
    } else if (listed != feeds.end()) {
      const WrittenFeed written = write_feed(listed->second, scale, decimals, most, true, source, number);
      if (written.value != output) {
        insert(written.text);
        output = written.value;
        in_step = output == original;
      }
    } else if (feeds_here && !in_step) {
      // Restore the original feed: its own F word in its own units (exact), or converted.
      if (original_inches == inches) {
        insert(original_digits);
        output = original;
      } else {
        const WrittenFeed written = write_feed(original, scale, most, most, false, source, number);
        insert(written.text);
        output = written.value;
      }
      in_step = true;
    }
    CWE_ASSERT(!feeds_here || lines.feed.at(number) == original,
               "the lexer tracks the feed the G-code reader gives each line");
    if (line.inches) inches = *line.inches;
  }
  return apply_edits(text, std::move(edits));
}

// ---------------------------------------------------------------------------------------------
// APT CLDATA

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
bool is_letter(char c) { return is_upper(c) || is_lower(c); }

// A line of the text, split as the CLDATA lexer splits it (LF, CR LF or a lone CR).
struct TextLine {
  std::size_t begin = 0, end = 0;  // its characters
  std::size_t next = 0;            // where the next line begins (after the line ending)
};

std::vector<TextLine> split_lines(std::string_view text) {
  std::vector<TextLine> lines;
  std::size_t position = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // byte-order mark
  while (position < text.size()) {
    TextLine line;
    line.begin = position;
    line.end = text.find_first_of("\r\n", position);
    if (line.end == std::string_view::npos) line.end = text.size();
    line.next = line.end;
    if (line.next < text.size() && text[line.next] == '\r') ++line.next;
    if (line.next < text.size() && text[line.next] == '\n') ++line.next;
    lines.push_back(line);
    position = line.next;
  }
  return lines;
}

// A record as the CLDATA lexer makes it, with where it starts in the text.
struct ClRecord {
  int line = 0;                     // its first line, from 1
  std::size_t start = 0;            // byte offset of its first non-blank character
  std::string major;                // upper case, blanks collapsed; empty for bare numbers
  bool bare_numbers = false;        // a line of numbers continuing a GOTO
  bool lower_case = false;          // its major word is written in lower case
  std::vector<std::string> fields;  // after the slash: trimmed, upper case
};

constexpr std::string_view kLiteralWords[] = {"PARTNO", "PPRINT", "INSERT", "TPRINT"};

// The records of the program up to FINI, joined over `$` continuations as the reader's Lexer
// joins them (the program has been read, so every record is complete).
std::vector<ClRecord> cldata_records(std::string_view text, const std::vector<TextLine>& lines) {
  std::vector<ClRecord> records;
  std::size_t index = 0;
  while (index < lines.size()) {
    const std::string_view first =
        text.substr(lines[index].begin, lines[index].end - lines[index].begin);
    std::size_t i = 0;
    while (i < first.size() && is_blank(first[i])) ++i;
    if (i == first.size() || first.substr(i, 2) == "$$") {
      ++index;  // blank or comment line
      continue;
    }
    ClRecord record;
    record.line = static_cast<int>(index) + 1;
    record.start = lines[index].begin + i;
    record.lower_case = is_lower(first[i]);

    // Literal records take their line as free text.
    std::size_t word_end = i;
    while (word_end < first.size() && is_letter(first[word_end])) ++word_end;
    std::string word;
    for (std::size_t k = i; k < word_end; ++k) word += to_upper(first[k]);
    if (std::find(std::begin(kLiteralWords), std::end(kLiteralWords), word) !=
            std::end(kLiteralWords) &&
        (word_end == first.size() || is_blank(first[word_end]) || first[word_end] == '/')) {
      record.major = word;
      records.push_back(std::move(record));
      ++index;
      continue;
    }

    std::string joined;  // upper case, continuation lines joined by a blank
    bool continued = false;
    for (std::size_t from = i; index < lines.size(); from = 0) {
      const std::string_view line =
          text.substr(lines[index].begin, lines[index].end - lines[index].begin);
      ++index;
      bool content = false, continues = false;
      for (std::size_t k = from; k < line.size(); ++k) {
        if (line[k] == '$') {
          continues = k + 1 >= line.size() || line[k + 1] != '$';
          break;
        }
        content = content || !is_blank(line[k]);
        joined.push_back(to_upper(line[k]));
      }
      if (continues) {
        joined.push_back(' ');
        continued = true;
        continue;
      }
      if (content || !continued) break;  // else a blank or comment line inside the record
    }

    std::size_t begin = 0;
    while (begin < joined.size() && is_blank(joined[begin])) ++begin;
    const std::size_t slash = joined.find('/', begin);
    std::size_t major_end = joined.size();
    if (slash != std::string::npos) {
      major_end = slash;
    } else if (begin < joined.size() && (is_digit(joined[begin]) || joined[begin] == '+' ||
                                         joined[begin] == '-' || joined[begin] == '.')) {
      record.bare_numbers = true;
      major_end = begin;
    }
    for (std::size_t k = begin; k < major_end; ++k) {
      if (is_blank(joined[k])) continue;
      if (k > begin && is_blank(joined[k - 1]) && !record.major.empty()) record.major += ' ';
      record.major += joined[k];
    }
    if (slash != std::string::npos) {
      std::size_t from = slash + 1;
      while (true) {
        const std::size_t comma = joined.find(',', from);
        const std::size_t to = comma == std::string::npos ? joined.size() : comma;
        std::size_t b = from, e = to;
        while (b < e && is_blank(joined[b])) ++b;
        while (e > b && is_blank(joined[e - 1])) --e;
        record.fields.push_back(joined.substr(b, e - b));
        if (comma == std::string::npos) break;
        from = comma + 1;
      }
    }
    const bool fini = record.major == "FINI";
    records.push_back(std::move(record));
    if (fini) break;  // the reader interprets nothing after FINI
  }
  return records;
}

// The feed state of the CLDATA reader: a feed in mm/min, or in mm/rev (times the spindle speed
// at each move) per revolution.
struct ClFeed {
  double value = 0.0;
  bool per_revolution = false;
  bool operator==(const ClFeed& other) const {
    return value == other.value && per_revolution == other.per_revolution;
  }
  bool operator!=(const ClFeed& other) const { return !(*this == other); }
};

// A FEDRAT record with the unit made explicit, so that it means the same whatever UNITS says.
struct ClFedrat {
  ClFeed feed;
  std::string number = "0";   // as written (upper case)
  std::string unit = "MMPM";  // MMPM, IPM, MMPR or IPR
  bool unit_first = false;    // FEDRAT/MMPM,250 (NX) rather than FEDRAT/250,MMPM
};

// The reader's feed_rate(): the first number is the feed, the unit one of six words.
ClFedrat read_fedrat(const ClRecord& record, double scale) {
  ClFedrat fedrat;
  std::string unit;
  bool number_seen = false;
  for (const std::string& field : record.fields) {
    if (!number_seen && !field.empty() &&
        (is_digit(field[0]) || field[0] == '+' || field[0] == '-' || field[0] == '.')) {
      fedrat.number = field[0] == '+' ? field.substr(1) : field;
      number_seen = true;
    } else if (!field.empty()) {
      unit = field;
      fedrat.unit_first = !number_seen;
    }
  }
  CWE_ASSERT(number_seen, "the reader accepted the FEDRAT");
  fedrat.feed.per_revolution = unit == "MMPR" || unit == "IPR" || unit == "PERREV";
  const double factor = unit == "MMPM" || unit == "MMPR" ? 1.0
                        : unit == "IPM" || unit == "IPR" ? kMillimetresPerInch
                                                         : scale;
  fedrat.feed.value = parse_signed(fedrat.number) * factor;
  const bool metric = factor == 1.0;
  fedrat.unit = fedrat.feed.per_revolution ? (metric ? "MMPR" : "IPR") : (metric ? "MMPM" : "IPM");
  return fedrat;
}

std::string rewrite_cldata(std::string_view text, const LineFeeds& feeds,
                           const std::string& source) {
  const FeedLines lines = feed_lines(read_cldata(text, source), feeds, source);
  if (feeds.empty()) return std::string(text);

  const std::vector<TextLine> text_lines = split_lines(text);
  const std::vector<ClRecord> records = cldata_records(text, text_lines);
  // Inserted lines end like the line they precede; before a last line without an ending, like
  // the first line that has one (LF when none has).
  std::string_view file_ending = "\n";
  for (const TextLine& line : text_lines) {
    if (line.next > line.end) {
      file_ending = text.substr(line.end, line.next - line.end);
      break;
    }
  }
  std::vector<Edit> edits;
  // Inserts `record_text` on a line of its own before line `number`, indented like it.
  const auto insert_line = [&](int number, const std::string& record_text) {
    const TextLine& line = text_lines[static_cast<std::size_t>(number - 1)];
    std::size_t indent = line.begin;
    while (indent < line.end && (text[indent] == ' ' || text[indent] == '\t')) ++indent;
    const std::string_view ending =
        line.next > line.end ? text.substr(line.end, line.next - line.end) : file_ending;
    edits.push_back({line.begin, 0,
                     std::string(text.substr(line.begin, indent - line.begin)) + record_text +
                         std::string(ending)});
  };

  // The program's precision: the most decimals its FEDRAT numbers have.
  std::optional<int> precision;
  for (const ClRecord& record : records) {
    if (record.major == "FEDRAT") {
      precision = std::max(precision.value_or(0), decimals_of(read_fedrat(record, 1.0).number));
    }
  }
  const int decimals_mm = std::min(precision.value_or(kDefaultDecimalsMm), kMostDecimalsMm);
  const int decimals_inch = std::clamp(precision.value_or(kDefaultDecimalsInch),
                                       kLeastDecimalsInch, kMostDecimalsInch);

  double scale = 1.0;  // mm per program unit (UNITS)
  ClFedrat original;   // the FEDRAT in force in the original program (none: 0 mm/min)
  ClFeed output;       // the feed in force in the rewritten program
  bool in_step = true;
  std::optional<std::size_t> circle;       // a CIRCLE waiting for its GOTO
  std::optional<std::size_t> goto_circle;  // the CIRCLE whose arc the last GOTO ended
  bool fedrat_after_circle = false;
  bool unit_first = false;  // how the program writes FEDRAT
  bool lower_case = false;  // how the program writes its major words
  const auto in_case = [&](const char* word) {
    return lower_case ? lower(word) : std::string(word);
  };

  for (std::size_t index = 0; index < records.size(); ++index) {
    const ClRecord& record = records[index];
    if (!record.bare_numbers) lower_case = record.lower_case;
    const std::string& word = record.major;
    const bool is_goto = word == "GOTO";
    // Only points continue a GOTO, on its circle (the reader's goto_circle_).
    std::optional<std::size_t> continued_circle;
    if (record.bare_numbers) continued_circle = goto_circle;
    goto_circle.reset();
    if (word == "UNITS") {
      scale = record.fields.at(0) == "MM" ? 1.0 : kMillimetresPerInch;
    } else if (word == "FEDRAT") {
      original = read_fedrat(record, scale);
      output = original.feed;
      in_step = true;
      unit_first = original.unit_first;
      if (circle) fedrat_after_circle = true;
    } else if (word == "CIRCLE") {
      circle = index;
      fedrat_after_circle = false;
    } else if (is_goto || word == "GODLTA" || record.bare_numbers) {
      // The CIRCLE whose arc this GOTO ends.
      const std::optional<std::size_t> arc_circle = is_goto ? circle : std::nullopt;
      if (is_goto) {
        circle.reset();
        goto_circle = arc_circle;
      }
      if (record.bare_numbers) goto_circle = continued_circle;
      if (lines.feed.count(record.line) == 0) continue;
      const auto listed = feeds.find(record.line);
      std::optional<ClFedrat> change;
      if (listed != feeds.end()) {
        // In the program's units.
        const bool inches = scale != 1.0;
        const WrittenFeed written =
            write_feed(listed->second, scale, inches ? decimals_inch : decimals_mm,
                       inches ? kMostDecimalsInch : kMostDecimalsMm, true, source, record.line);
        if (ClFeed{written.value, false} != output) {
          change = ClFedrat{{written.value, false}, written.text, inches ? "IPM" : "MMPM",
                            unit_first};
        }
      } else if (!in_step) {
        change = original;
        change->unit_first = unit_first;
      }
      if (change) {
        const std::string unit = lower_case ? lower(change->unit) : change->unit;
        const std::string fedrat =
            in_case("FEDRAT/") +
            (change->unit_first ? unit + "," + change->number : change->number + "," + unit);
        if (record.bare_numbers) {
          // No record may stand between a GOTO and its points: the point becomes a GOTO of its
          // own (on a copy of the circle without TIMES when it continues an arc), which the
          // reader makes into the same move, and the points after it continue that GOTO.
          insert_line(record.line, fedrat);
          if (continued_circle) {
            const std::vector<std::string>& c = records[*continued_circle].fields;
            insert_line(record.line, fmt::format("{}{},{},{},{},{},{},{}", in_case("CIRCLE/"), c[0],
                                                 c[1], c[2], c[3], c[4], c[5], c[6]));
          }
          edits.push_back({record.start, 0, in_case("GOTO/")});
        } else if (arc_circle && !fedrat_after_circle) {
          insert_line(records[*arc_circle].line, fedrat);  // CIRCLE and GOTO stay together
        } else {
          insert_line(record.line, fedrat);
        }
        output = change->feed;
        in_step = listed == feeds.end() || output == original.feed;
      }
      CWE_ASSERT(original.feed.per_revolution || lines.feed.at(record.line) == original.feed.value,
                 "the lexer tracks the feed the CLDATA reader gives each line");
    }
  }
  return apply_edits(text, std::move(edits));
}

}  // namespace

std::string rewrite_feeds(std::string_view text, ToolpathFormat format, const LineFeeds& feeds,
                          const std::string& source, const FeedRewriteOptions& options) {
  return format == ToolpathFormat::kGcode ? rewrite_gcode(text, feeds, source, options.gcode)
                                          : rewrite_cldata(text, feeds, source);
}

}  // namespace cwe
