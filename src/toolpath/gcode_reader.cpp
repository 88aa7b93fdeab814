#include "cwe/toolpath/gcode_reader.hpp"

// RS274NGC as LinuxCNC 2.9 interprets it (src/emc/rs274ngc: interp_read.cc reads a line into a
// block, interp_check.cc checks which words go together, interp_convert.cc, interp_arc.cc and
// interp_cycles.cc execute it). The structure below follows LinuxCNC's so that each behaviour can
// be compared with its counterpart there; docs/gcode.md lists them and how each was confirmed
// with LinuxCNC's own interpreter (`rs274`).
//
// Like LinuxCNC, the interpreter keeps positions in program units (inch under G20, mm under G21)
// and converts the current position when the units change; moves are scaled to millimetres only
// when they are emitted. Tolerances are in program units for the same reason.

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <optional>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "cwe/core/text_file.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "gcode_compensation.hpp"
#include "gcode_expression.hpp"
#include "gcode_tolerance.hpp"

namespace cwe {
namespace {

// How far above the previous depth a G73/G83 peck stops its rapid (LinuxCNC G83_RAPID_DELTA),
// inch; 0.254 mm under G21.
constexpr double kPeckClearanceInch = 0.010;

// A canned cycle that expands to more moves than this is refused: it is a typo (Q far smaller
// than the hole, a huge L) that would otherwise exhaust memory.
constexpr double kMaxCycleMoves = 1e6;

// G codes as LinuxCNC stores them: ten times the number, G59.1 is 591.
constexpr int kG10 = 100, kG28 = 280, kG28_1 = 281, kG30 = 300, kG30_1 = 301, kG33 = 330,
              kG33_1 = 331, kG52 = 520,
              kG53 = 530, kG92 = 920, kG92_1 = 921, kG92_2 = 922, kG92_3 = 923;
constexpr int kG0 = 0, kG1 = 10, kG2 = 20, kG3 = 30, kG4 = 40, kG5 = 50, kG5_1 = 51, kG17 = 170, kG18 = 180, kG19 = 190,
              kG20 = 200, kG40 = 400, kG41 = 410, kG41_1 = 411, kG42 = 420, kG42_1 = 421, kG43 = 430, kG64 = 640, kG73 = 730, kG80 = 800, kG81 = 810, kG82 = 820,
              kG83 = 830, kG90_1 = 901, kG91 = 910, kG99 = 990;

// LinuxCNC's modal groups (interp_internal.hh GM_*), indices into Block::g.
enum GroupIndex : int {
  kGroupNonModal = 0,
  kGroupMotion = 1,
  kGroupPlane = 2,
  kGroupDistance = 3,
  kGroupArcDistance = 4,
  kGroupFeedMode = 5,
  kGroupUnits = 6,
  kGroupCutterComp = 7,
  kGroupToolLength = 8,
  kGroupRetract = 10,
  kGroupCoordSystem = 12,
  kGroupPathControl = 13,
  kGroupSpindleMode = 14,
  kGroupLathe = 15,
  kGroupCount = 16
};

// M-code groups (LinuxCNC's m_modes indices).
enum MGroupIndex : int {
  kMGroupStop = 4,
  kMGroupToolChange = 6,
  kMGroupSpindle = 7,
  kMGroupCoolant = 8,
  kMGroupCount = 11
};

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

std::string g_name(int code) {
  return code % 10 == 0 ? fmt::format("G{}", code / 10)
                        : fmt::format("G{}.{}", code / 10, code % 10);
}

bool is_cycle(int motion) {
  return motion == kG73 || motion == kG81 || motion == kG82 || motion == kG83;
}

// A character for a message: itself if printable ASCII, its code otherwise.
std::string describe_char(unsigned char c) {
  if (c >= 0x21 && c < 0x7f) return fmt::format("'{}'", static_cast<char>(c));
  return fmt::format("0x{:02X}", static_cast<unsigned>(c));
}

// One word of a block: the value and the column of its letter.
struct Word {
  bool present = false;
  double value = 0.0;
  int column = 0;
};

// One line read into words, as LinuxCNC's block_struct.
struct Block {
  std::array<Word, 26> words{};  // by letter, 'a' to 'z'
  std::array<int, kGroupCount> g{};
  std::array<int, kGroupCount> g_column{};
  std::array<int, kMGroupCount> m{};
  std::array<int, kMGroupCount> m_column{};
  std::vector<gcode::ParameterSetting> settings;  // applied after the line is read, in order

  Block() {
    g.fill(-1);
    m.fill(-1);
  }
  Word& operator[](char letter) { return words[static_cast<std::size_t>(letter - 'a')]; }
  const Word& operator[](char letter) const {
    return words[static_cast<std::size_t>(letter - 'a')];
  }
  bool has(char letter) const { return (*this)[letter].present; }
  bool has_axis() const { return has('x') || has('y') || has('z'); }
  // Polar coordinates: @ radius, ^ angle (degrees), about the XY origin.
  Word polar_radius, polar_angle;
  bool has_polar() const { return polar_radius.present || polar_angle.present; }
  // Column of the first axis word, for errors about a modal motion.
  int first_axis_column() const {
    int column = 0;
    for (char a : {'x', 'y', 'z'}) {
      const Word& w = (*this)[a];
      if (w.present && (column == 0 || w.column < column)) column = w.column;
    }
    return column;
  }
};

using gcode::CompactLine;

enum class Plane { kXY, kXZ, kYZ };

// Axis indices of a plane in LinuxCNC's canonical order: first and second in-plane axes and the
// axis normal to the plane. (first, second, normal) is right-handed, so a positive rotation
// (G3) is counter-clockwise about +normal: XY → (X, Y, Z), XZ → (Z, X, Y), YZ → (Y, Z, X).
struct PlaneAxes {
  int first, second, normal;
  char first_letter, second_letter;  // axis letters, for messages
  char first_offset, second_offset;  // the centre words: I, J or K
  char forbidden_offset;             // the centre word for the normal axis
};

PlaneAxes plane_axes(Plane plane) {
  switch (plane) {
    case Plane::kXY:
      return {0, 1, 2, 'X', 'Y', 'i', 'j', 'k'};
    case Plane::kXZ:
      return {2, 0, 1, 'Z', 'X', 'k', 'i', 'j'};
    case Plane::kYZ:
      break;
  }
  return {1, 2, 0, 'Y', 'Z', 'j', 'k', 'i'};
}

const char* plane_name(Plane plane) {
  switch (plane) {
    case Plane::kXY:
      return "XY";
    case Plane::kXZ:
      return "XZ";
    case Plane::kYZ:
      break;
  }
  return "YZ";
}

class Interpreter {
 public:
  // `mapped`: the main program's file, when it was mapped (its pages are let go as reading moves
  // on); `sink`: where moves go as they are made (none: into the Toolpath).
  Interpreter(std::string_view text, const std::string& source, const GcodeOptions& options,
              const MoveSink* sink = nullptr, MappedText* mapped = nullptr)
      : source_(source), options_(options), sink_(sink) {
    inches_ = options.initial_units == ProgramUnits::kInches;
    if (options.machine) set_up_machine(*options.machine);
    tip_ = options.initial_position;
    position_ = (tip_ + frame_offset_) / scale() - origin_offset_;
    files_.push_back(std::make_unique<ProgramFile>(ProgramFile{source, nullptr, mapped, text}));
    result_.sources = {source};
    result_.units = options.initial_units;
    here_.source = source;
    parameters_.set_predefined([this](std::string_view name) { return predefined(name); });
    publish_state();
  }
  Interpreter(const Interpreter&) = delete;  // the parameters' lookup holds `this`
  Interpreter& operator=(const Interpreter&) = delete;

  Toolpath run();

 private:
  [[noreturn]] void fail(int column, const std::string& message) const {
    throw InputError(SourceLocation{source_, line_, column}, message);
  }
  // The first kWarningsKept warnings, then a count (a long program may warn on every line).
  static constexpr std::size_t kWarningsKept = 1000;
  std::size_t warnings_dropped_ = 0;
  bool closing_ = false;  // the program's end: its warnings are always kept
  // Codes read that change nothing on the tip path cwe makes (coolant, dwell, pauses, tool length
  // offsets, path control): one warning per kind at the end, where it first appeared, with the
  // number of lines.
  struct Unmodelled {
    const char* what;
    SourceLocation first;
    int lines = 0;
  };
  std::vector<Unmodelled> unmodelled_;
  void note_unmodelled(const char* what, int column) {
    for (Unmodelled& u : unmodelled_) {
      if (u.what == what) {
        ++u.lines;
        return;
      }
    }
    unmodelled_.push_back({what, SourceLocation{source_, line_, column}, 1});
  }
  void warn(int line, int column, const std::string& message) {
    if (result_.warnings.size() >= kWarningsKept && !closing_) {
      ++warnings_dropped_;
      return;
    }
    result_.warnings.push_back({SourceLocation{source_, line, column}, message});
  }
  double scale() const { return inches_ ? kMillimetresPerInch : 1.0; }

  // Reading.
  CompactLine compact(std::string_view raw) const;
  Block read_block(const CompactLine& line, std::size_t i) const;
  double read_number(const CompactLine& line, std::size_t& i, int word_column, char letter) const;
  gcode::ValueReader values(const CompactLine& line) const {
    return gcode::ValueReader(line, here_, parameters_);
  }
  int read_integer(const CompactLine& line, std::size_t& i, int word_column, char letter) const;
  void read_g(const CompactLine& line, std::size_t& i, int column, Block& block) const;
  void read_m(const CompactLine& line, std::size_t& i, int column, Block& block) const;

  // Parameters: the predefined named ones (LinuxCNC's lookup_named_param), and the numbered
  // ones that mirror the state (#5400 the tool, #5420-#5422 the position) after each line.
  std::optional<double> predefined(std::string_view name) const;
  void publish_state();

  // Executing.
  bool execute(const Block& block);  // false once the program has ended
  int motion_to_be(const Block& block, int& column) const;
  void check_words(const Block& block, int motion) const;
  Vec3 find_end(const Block& block) const;
  Vec2 polar_end(const Block& block, const Vec3& from) const;
  void straight(const Block& block, int motion, int column);
  void arc(const Block& block, int motion, int column);
  void synchronised(const Block& block, int motion, int column);
  void spline(const Block& block, int motion, int column);
  Vec2 spline_ij_ = Vec2::Zero();  // G5's first control point offset when I, J are left out
  Vec2 arc_center(const Block& block, int motion, int column, const Vec2& start,
                  const Vec2& end) const;
  void cycle(const Block& block, int motion, int column);

  // Cutter radius compensation (gcode_compensation.hpp), in the plane's coordinates.
  gcode::CutterCompensation compensation_{
      [this](const gcode::CompensatedMove& m) { emit_compensated(m); }};
  bool warned_no_tool_radius_ = false;
  void compensation_on(const Block& block, int code);
  void compensation_off(int column);
  double tool_radius(int tool, int column);  // program units
  void refuse_with_compensation(bool refused, int column, const char* message) const {
    if (refused && compensation_.on()) fail(column, message);
  }
  template <class F>
  auto compensating(int column, F&& f) {
    try {
      return f();
    } catch (const gcode::CompensationError& e) {
      fail(column, e.what());
    }
  }
  Vec3 to_plane(const Vec3& p) const {
    const PlaneAxes a = plane_axes(plane_);
    return {p[a.first], p[a.second], p[a.normal]};
  }
  Vec3 from_plane(const Vec3& q) const {
    const PlaneAxes a = plane_axes(plane_);
    Vec3 p;
    p[a.first] = q.x();
    p[a.second] = q.y();
    p[a.normal] = q.z();
    return p;
  }
  void set_units(bool inches);
  void note_unmodelled_codes(const Block& block);

  // Emitting moves (positions in program units). A move starts where the last one ended (tip_),
  // which is machine(position_) except after G40, where position_ becomes the programmed point.
  Move new_move(MotionMode mode) const;
  void push(const Move& move);
  void emit_line(MotionMode mode, const Vec3& to);
  void emit_arc(const Vec3& start, const Vec3& end, const Vec2& center, int turn, bool may_close,
                int column, Move move);
  void emit_compensated(const gcode::CompensatedMove& m);
  void cycle_traverse(double x, double y, double z) { emit_line(MotionMode::kRapid, {x, y, z}); }
  void cycle_feed(double x, double y, double z) { emit_line(MotionMode::kFeed, {x, y, z}); }

  // Program text: the main program and the subroutine files it calls by name, each read once.
  struct ProgramFile {
    std::string name;
    std::unique_ptr<MappedText> owned;  // a subroutine file's (the main program's is the caller's)
    MappedText* mapped = nullptr;       // the file, when mapped
    std::string_view text;
  };
  // A place in the program: the file, the byte offset of a line and its number there (from 1;
  // 0 before the first line).
  struct Position {
    int file = 0;
    std::size_t offset = 0;
    int line = 0;
  };
  // The next line to read, or false at the end of the current file.
  bool next_line(std::string_view& raw);
  // Runs one line; false when reading ends (a subroutine file after the program's end).
  bool run_line(std::string_view raw);
  // At the end of the main program: what was left open is an error.
  void end_of_file();
  bool seen_content_ = false;  // a line with something other than blanks (main program)
  int last_content_line_ = 0;
  bool percent_opened_ = false;
  bool ended_ = false;  // M2, M30 or the closing '%'
  int ignored_lines_ = 0, first_ignored_ = 0;
  void go_to(const Position& at);
  int file_of(const std::string& name);

  // O-word control flow (LinuxCNC's interp_o_word.cc): subroutines, conditions and loops.
  // kFanuc is a bare "O100" (a Fanuc-style subprogram, or a program number); kM98 and kM99 are
  // Fanuc-style calls and returns.
  enum class OType { kNone, kSub, kEndsub, kCall, kDo, kWhile, kRepeat, kIf, kElseif, kElse,
                     kEndif, kBreak, kContinue, kEndwhile, kEndrepeat, kReturn, kFanuc, kM98,
                     kM99 };
  struct OLine {
    OType type = OType::kNone;
    std::string name;  // sub, endsub, call, return: the label; others: "sub#label"
    std::string label;  // as written, for messages
    double test = 0.0;  // while, if, elseif, repeat
    std::vector<double> args;  // call
    int repeats = -1;          // M98 L (-1: none)
    Position at;        // the line's own position
  };
  struct OffsetEntry {
    OType type = OType::kNone;
    Position at;
    int repeat_count = -1;
  };
  // The modal state M70/M73 save and M72 restores (LinuxCNC's save_settings: units, F, S,
  // plane, distance modes, coordinate system, retract mode, whether G92 applies, spindle,
  // coolant; not the motion mode).
  struct ModalState {
    bool inches = false;
    double feed = 0.0;  // program units per minute, as LinuxCNC's feed_rate
    double speed = 0.0;
    Plane plane = Plane::kXY;
    bool incremental = false, arc_absolute = false, retract_to_r = true, g92_applied = false;
    int origin = 1;
    SpindleDirection spindle = SpindleDirection::kStopped;
    bool mist = false, flood = false;
  };
  struct Frame {
    std::string sub_name;  // empty at the main level
    Position return_to;    // where the caller goes on (kept in the caller's frame)
    std::array<double, 30> saved{};  // the caller's #1-#30
    std::optional<ModalState> state;  // M70/M73
    bool restore_on_return = false;   // M73
    bool m98 = false;                 // entered by M98 (returns with M99; #1-#30 shared)
    int m98_loop = -1;                // the M98 L repeats left, in the caller's frame
  };
  ModalState modal_state() const;
  void restore(const ModalState& saved);
  static constexpr int kMaxCallLevels = 10;  // LinuxCNC's INTERP_SUB_ROUTINE_LEVELS
  static constexpr std::size_t kSubroutineArguments = 30;
  std::size_t after_line_number(const CompactLine& line) const;
  OLine read_o(const CompactLine& line, std::size_t i);
  std::optional<OLine> read_m98(const CompactLine& line, std::size_t i);
  void control(const OLine& o);
  void call(const OLine& o);
  void give_back(const OLine& o);  // endsub, return
  void save_offset(const OLine& o);
  OffsetEntry& find_offset(const OLine& o);
  void back_to(const OLine& o);
  std::optional<std::string> find_subroutine_file(const std::string& name) const;
  const char* o_name(OType type) const;

  std::string source_;  // the file of the current line
  GcodeOptions options_;
  const MoveSink* sink_ = nullptr;
  std::vector<std::unique_ptr<ProgramFile>> files_;
  Position at_;                  // the next line to read
  std::size_t line_offset_ = 0;  // the current line's offset
  Toolpath result_;
  int line_ = 0;
  SourceLocation here_;  // source_ and line_, for the value reader's errors
  gcode::Parameters parameters_;
  std::map<std::string, OffsetEntry> offsets_;
  // The label being skipped to, and the subroutine being looked for (empty: none).
  std::string skipping_o_, skipping_to_sub_;
  Position skipping_start_;
  bool defining_sub_ = false;
  std::string sub_name_;  // the subroutine being defined or run (empty: none)
  bool executed_if_ = false, doing_break_ = false, doing_continue_ = false;
  double return_value_ = 0.0;
  bool value_returned_ = false;
  std::vector<Frame> frames_ = std::vector<Frame>(1);
  // Loop iterations since the last move: a loop that runs this often without moving never ends.
  static constexpr long kMaxIdleIterations = 10'000'000;
  long idle_iterations_ = 0;

  // Modal state, as LinuxCNC's setup_struct.
  Vec3 position_ = Vec3::Zero();  // program units
  Vec3 tip_ = Vec3::Zero();       // machine coordinates, mm: where the last move ended
  bool inches_ = false;
  bool units_seen_ = false;
  Plane plane_ = Plane::kXY;
  bool incremental_ = false;      // G91
  bool arc_absolute_ = false;     // G90.1 (LinuxCNC starts in G91.1)
  bool retract_to_r_ = true;      // G99 (LinuxCNC's initial retract mode), false: G98
  int motion_mode_ = kG80;        // LinuxCNC starts with no motion mode (G80)
  double feed_mm_per_min_ = 0.0;  // physical: LinuxCNC's canon converts F when it is set
  double spindle_speed_ = 0.0;
  SpindleDirection spindle_ = SpindleDirection::kStopped;
  bool mist_ = false, flood_ = false;  // M7, M8; M9 stops both
  int selected_tool_ = 0;
  int loaded_tool_ = 0;
  // Coordinate systems (program units): the selected work offset G54-G59.3 (1-9, its values in
  // #5221… as LinuxCNC keeps them, in mm) and the G92/G52 offset. Moves are emitted in machine
  // coordinates, position_ + origin_offset_ + axis_offset_.
  int origin_index_ = 1;
  Vec3 origin_offset_ = Vec3::Zero();
  Vec3 axis_offset_ = Vec3::Zero();
  bool warned_machine_ = false;
  bool warned_tool_data_ = false;
  bool warned_zero_normal_offset_ = false;
  // Machine coordinates (mm) of a point in program coordinates, and the frame moves are reported
  // in (the machine definition's work system; without one, machine coordinates).
  Vec3 machine_mm(const Vec3& p) const { return (p + origin_offset_ + axis_offset_) * scale(); }
  Vec3 machine(const Vec3& p) const { return machine_mm(p) - frame_offset_; }
  Vec3 frame_offset_ = Vec3::Zero();  // mm
  void set_up_machine(const MachineDefinition& machine);
  void check_travel(const Move& move) const;
  Vec3 stored_offset(int first_parameter) const;  // #first … #first+2, mm → program units
  void set_stored_offset(int first_parameter, const Vec3& offset);
  void select_origin(int origin);
  void setup_offsets(const Block& block);      // G10 L2, L20
  void axis_offsets(const Block& block, int code);  // G52, G92, G92.1-G92.3
  void go_home(const Block& block, int code);  // G28, G30
  void warn_machine(const char* what);
  // Canned-cycle memory (LinuxCNC cycle_r, cycle_cc, cycle_p, cycle_q, cycle_il).
  double cycle_r_ = 0.0, cycle_cc_ = 0.0, cycle_p_ = 0.0, cycle_q_ = 0.0;
  bool cycle_initial_level_set_ = false;
  double cycle_initial_level_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// Reading

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

// ---------------------------------------------------------------------------------------------
// Parameters

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
    fail(1, fmt::format("G{}: coordinate system rotation (G10 L2 R) is not supported",
                        origin < 7 ? fmt::format("{}", 53 + origin)
                                   : fmt::format("59.{}", origin - 6)));
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
    if (!warned_tool_data_) {
      warned_tool_data_ = true;
      warn(line_, column, fmt::format("G10 L{} (tool table data) changes nothing on the tip path "
                                      "cwe reads; later G10 L1, L10 and L11 lines say nothing",
                                      l));
    }
    return;
  }
  if (l != 2 && l != 20) fail(block['l'].column, fmt::format("G10 L{}: expected L2 or L20", l));
  const double p_value = block['p'].value;
  int p = static_cast<int>(p_value + 0.0001);
  if (!(p_value >= 0.0) || p > 9 || std::abs(p_value - p) > 0.0001) {
    fail(block['p'].column, fmt::format("P value out of range with G10 L{}: {:g} (expected 0 to 9)",
                                        l, p_value));
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
  const Vec3 home =
      stored_offset(code == kG28 ? 5161 : 5181) - origin_offset_ - axis_offset_;
  const bool any = block.has_axis();
  for (int a = 0; a < 3; ++a) {
    if (!any || block[static_cast<char>('x' + a)].present) end[a] = home[a];
  }
  emit_line(MotionMode::kRapid, end);
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
  plane_ = saved.plane;
  incremental_ = saved.incremental;
  arc_absolute_ = saved.arc_absolute;
  retract_to_r_ = saved.retract_to_r;
  select_origin(saved.origin);
  if (saved.g92_applied != (parameters_.numbered(5210) != 0.0)) {
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
      fail(block['l'].column,
           "lathe tool orientation (L with G41.1 or G42.1) is not supported");
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
}

// The radius of `tool` in program units; 0 for no tool (T0), as LinuxCNC's empty spindle.
double Interpreter::tool_radius(int tool, int column) {
  if (tool == 0) {
    if (!warned_no_tool_radius_) {
      warned_no_tool_radius_ = true;
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
    note_unmodelled("tool length offsets (G43 H, G49): not applied; the program is read in tool "
                    "tip coordinates, as with the right offset in effect",
                    block.g_column[kGroupToolLength]);
  }
  if (block.g[kGroupPathControl] != -1) {
    note_unmodelled("path control (G61, G61.1, G64 P Q): the programmed path is followed exactly; "
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

// The machine's offsets and stored positions become LinuxCNC's parameters; G54 is selected.
void Interpreter::set_up_machine(const MachineDefinition& machine) {
  for (int k = 0; k < 9; ++k) set_stored_offset(5221 + 20 * k, machine.work_offsets[k] / scale());
  set_stored_offset(5161, machine.g28 / scale());
  set_stored_offset(5181, machine.g30 / scale());
  origin_offset_ = stored_offset(5221);
  frame_offset_ = machine.work_offsets[static_cast<std::size_t>(machine.frame - 1)];
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
    if (box.max[a] > travel.max[a] + tol::kLength) {
      fail(0, fmt::format("the move goes beyond the machine's travel: {} {:.3f} mm, its limit {:.3f} "
                          "mm (machine coordinates)",
                          axis, box.max[a], travel.max[a]));
    }
    if (box.min[a] < travel.min[a] - tol::kLength) {
      fail(0, fmt::format("the move goes beyond the machine's travel: {} {:.3f} mm, its limit {:.3f} "
                          "mm (machine coordinates)",
                          axis, box.min[a], travel.min[a]));
    }
  }
}

void Interpreter::warn_machine(const char* what) {
  if (warned_machine_ || options_.machine) return;
  warned_machine_ = true;
  warn(line_, 0, fmt::format("{}: machine coordinates are taken equal to the program's with "
                             "zero work offsets and no tool length offset (the stored positions "
                             "#5161-#5186 start at 0, as in LinuxCNC without a parameter file)",
                             what));
}

void Interpreter::publish_state() {
  parameters_.set_numbered(5400, static_cast<double>(loaded_tool_));
  for (int axis = 0; axis < 3; ++axis) parameters_.set_numbered(5420 + axis, position_[axis]);
}

// ---------------------------------------------------------------------------------------------
// Executing (LinuxCNC's check_items and execute_block, in its order)

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
    const int at = block.polar_radius.present ? block.polar_radius.column : block.polar_angle.column;
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
    if (!block.has('l')) fail(block.g_column[kGroupNonModal], "line with G10 does not have L2 or L20");
    if (!block.has('p')) fail(block.g_column[kGroupNonModal], "line with G10 does not have a P word");
  }
  if (block.has('r') && !arc && !is_cycle(motion) && !g10) {
    fail(block['r'].column, "R word with no G2, G3 or canned cycle to use it");
  }
  if (block.has('p') && !arc && motion != kG5 && motion != kG82 &&
      block.g[kGroupNonModal] != kG4 && !g10 && block.g[kGroupPathControl] != kG64) {
    fail(block['p'].column, "P word with no G2, G3, G4, G5, G64 or G82 to use it");
  }
  const bool m61 = block.m[kMGroupToolChange] == 61;
  if (m61 && !block.has('q')) fail(block.m_column[kMGroupToolChange], "need Q parameter with M61");
  if (m61 && (block['q'].value < 0.0 || std::abs(block['q'].value - std::round(block['q'].value)) >
                                            tol::kGcodeIntegerWord)) {
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
  refuse_with_compensation(zero == kG52 || zero == kG92 || zero == kG92_1 || zero == kG92_2 ||
                               zero == kG92_3,
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
    compensating(block.m_column[kMGroupStop],
                 [&] { compensation_.release(to_plane(position_)); });
  } else if (stop != -1) {
    compensating(block.m_column[kMGroupStop], [&] { compensation_.stop(to_plane(position_)); });
  }
  if (stop == 99) {
    // M99 in the main program: LinuxCNC starts the program over, forever.
    warn(line_, block.m_column[kMGroupStop],
         "M99 in the main program: LinuxCNC would run the program again and again; cwe reads it "
         "once, as if M99 were M30");
  }
  return stop != 2 && stop != 30 && stop != 99;  // M0, M1 (pauses) do not change the path
}

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
    if (r.present && a.present) return {r.value * std::cos(a.value * degree),
                                        r.value * std::sin(a.value * degree)};
    if (r.present) {
      if (x == 0.0 && y == 0.0) fail(column, "must specify angle in polar coordinate if at the origin");
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
    result_.moves.push_back(move);
  }
  tip_ = move.end;
  idle_iterations_ = 0;
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
  refuse_with_compensation(true, column,
                           "cannot use G33 or G33.1 with cutter radius compensation on");
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
  compensation_.straight_move_made();
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
    fail(column, "the move just after exiting cutter compensation mode must be straight, not an arc");
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
      if (!warned_zero_normal_offset_) {
        warned_zero_normal_offset_ = true;
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
    const double theta = right ? chord_angle - kPi / 2.0 : chord_angle + kPi / 2.0;
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
    const double theta = block.polar_angle.present ? block.polar_angle.value * kPi / 180.0
                                                   : std::atan2(bb, aa);
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
        fail(column, "incremental motion with polar coordinates is indeterminate when at the origin");
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
  for (;;) {
    std::string_view raw;
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

// ---------------------------------------------------------------------------------------------
// O-words (LinuxCNC's read_o, convert_control_functions, execute_call, execute_return,
// control_back_to, control_save_offset)

const char* Interpreter::o_name(OType type) const {
  switch (type) {
    case OType::kNone: return "none";
    case OType::kSub: return "sub";
    case OType::kEndsub: return "endsub";
    case OType::kCall: return "call";
    case OType::kDo: return "do";
    case OType::kWhile: return "while";
    case OType::kRepeat: return "repeat";
    case OType::kIf: return "if";
    case OType::kElseif: return "elseif";
    case OType::kElse: return "else";
    case OType::kEndif: return "endif";
    case OType::kBreak: return "break";
    case OType::kContinue: return "continue";
    case OType::kEndwhile: return "endwhile";
    case OType::kEndrepeat: return "endrepeat";
    case OType::kFanuc: return "(Fanuc-style subprogram)";
    case OType::kM98: return "M98";
    case OType::kM99: return "M99";
    case OType::kReturn: break;
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
      {"sub", OType::kSub},           {"endsub", OType::kEndsub},
      {"call", OType::kCall},         {"do", OType::kDo},
      {"while", OType::kWhile},       {"repeat", OType::kRepeat},
      {"if", OType::kIf},             {"elseif", OType::kElseif},
      {"else", OType::kElse},         {"endif", OType::kEndif},
      {"break", OType::kBreak},       {"continue", OType::kContinue},
      {"endwhile", OType::kEndwhile}, {"endrepeat", OType::kEndrepeat},
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
    fail(line.column(i), "unknown O-word command: expected sub, endsub, call, do, while, repeat, "
                         "if, elseif, else, endif, break, continue, endwhile, endrepeat or return");
  }
  // Subroutine names are global; other labels belong to the subroutine they are in.
  const bool global = o.type == OType::kSub || o.type == OType::kEndsub ||
                      o.type == OType::kCall || o.type == OType::kReturn;
  if (global) {
    o.name = o.label;
  } else {
    const std::string sub = frames_.size() > 1 ? frames_.back().sub_name
                                                : (defining_sub_ ? sub_name_ : std::string());
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
          fail(line.column(i), fmt::format("more than {} subroutine arguments",
                                           kSubroutineArguments));
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
        fail(line.column(i), fmt::format("o{} {}: a bracketed expression must follow",
                                         o.label, o_name(o.type)));
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
    if (std::filesystem::is_regular_file(candidate, error)) return candidate.string();
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
    if (++idle_iterations_ > kMaxIdleIterations) {
      fail(1, fmt::format("o{} {}: {} loop iterations and calls without a move: the program "
                          "never ends (LinuxCNC would run it forever)",
                          o.label, o_name(o.type), kMaxIdleIterations));
    }
    Position at = it->second.at;
    at.line -= 1;  // the line is read again
    go_to(at);
    return;
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

}  // namespace

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
  return Interpreter(text, source, options).run();
}

Toolpath read_gcode(std::string_view text, const std::string& source, const GcodeOptions& options,
                    const MoveSink& sink) {
  return Interpreter(text, source, options, &sink).run();
}

Toolpath read_gcode_file(const std::string& path, const GcodeOptions& options) {
  MappedText file(path, "G-code file");
  return Interpreter(file.text(), path, options, nullptr, &file).run();
}

Toolpath read_gcode_file(const std::string& path, const GcodeOptions& options,
                         const MoveSink& sink) {
  MappedText file(path, "G-code file");
  return Interpreter(file.text(), path, options, &sink, &file).run();
}

}  // namespace cwe
