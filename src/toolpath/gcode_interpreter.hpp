#pragma once
// The G-code interpreter behind read_gcode (include/cwe/toolpath/gcode_reader.hpp); private to the
// toolpath module.
//
// RS274NGC as LinuxCNC 2.9 interprets it (src/emc/rs274ngc: interp_read.cc reads a line into a
// block, interp_check.cc checks which words go together, interp_convert.cc, interp_arc.cc and
// interp_cycles.cc execute it). The structure below follows LinuxCNC's so that each behaviour can
// be compared with its counterpart there; docs/gcode.md lists them and how each was confirmed
// with LinuxCNC's own interpreter (`rs274`).
//
// Like LinuxCNC, the interpreter keeps positions in program units (inch under G20, mm under G21)
// and converts the current position when the units change; moves are scaled to millimetres only
// when they are emitted. Tolerances are in program units for the same reason.
//
// The interpreter's work is spread over these files, each following its LinuxCNC counterparts:
//  - gcode_reader.cpp: the program's lines (next_line, run), reading a line into a block
//    (interp_read.cc), and the public functions;
//  - gcode_execute.cpp: checking and executing a block in LinuxCNC's order (interp_check.cc,
//    execute_block), the modal state, predefined parameters, cutter compensation on and off;
//  - gcode_motion.cpp: straight moves, arcs, splines, spindle-synchronised moves and canned cycles
//    (interp_convert.cc, interp_arc.cc, interp_cycles.cc), and emitting moves;
//  - gcode_coordinates.cpp: work systems, G10, G92/G52, G28/G30, the machine definition;
//  - gcode_owords.cpp: O-word subroutines, conditions and loops (interp_o_word.cc);
//  - gcode_expression.{hpp,cpp}: parameters and expressions; gcode_compensation.{hpp,cpp}: cutter
//    radius compensation's geometry.

#include <array>
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/toolpath/gcode_reader.hpp"
#include "gcode_compensation.hpp"
#include "gcode_expression.hpp"

namespace cwe::gcode {

// How far above the previous depth a G73/G83 peck stops its rapid (LinuxCNC G83_RAPID_DELTA),
// inch; 0.254 mm under G21.
constexpr double kPeckClearanceInch = 0.010;

// A canned cycle that expands to more moves than this is refused: it is a typo (Q far smaller
// than the hole, a huge L) that would otherwise exhaust memory.
constexpr double kMaxCycleMoves = 1e6;

// G codes as LinuxCNC stores them: ten times the number, G59.1 is 591.
constexpr int kG10 = 100, kG28 = 280, kG28_1 = 281, kG30 = 300, kG30_1 = 301, kG33 = 330,
              kG33_1 = 331, kG52 = 520, kG53 = 530, kG92 = 920, kG92_1 = 921, kG92_2 = 922,
              kG92_3 = 923;
constexpr int kG0 = 0, kG1 = 10, kG2 = 20, kG3 = 30, kG4 = 40, kG5 = 50, kG5_1 = 51, kG17 = 170,
              kG18 = 180, kG19 = 190, kG20 = 200, kG40 = 400, kG41 = 410, kG41_1 = 411, kG42 = 420,
              kG42_1 = 421, kG43 = 430, kG64 = 640, kG73 = 730, kG80 = 800, kG81 = 810, kG82 = 820,
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

inline std::string g_name(int code) {
  return code % 10 == 0 ? fmt::format("G{}", code / 10)
                        : fmt::format("G{}.{}", code / 10, code % 10);
}

inline bool is_cycle(int motion) {
  return motion == kG73 || motion == kG81 || motion == kG82 || motion == kG83;
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

inline PlaneAxes plane_axes(Plane plane) {
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

inline const char* plane_name(Plane plane) {
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
  int compensation_code_ = kG40;  // the code that turned compensation on (G40: off)
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
  enum class OType {
    kNone,
    kSub,
    kEndsub,
    kCall,
    kDo,
    kWhile,
    kRepeat,
    kIf,
    kElseif,
    kElse,
    kEndif,
    kBreak,
    kContinue,
    kEndwhile,
    kEndrepeat,
    kReturn,
    kFanuc,
    kM98,
    kM99
  };
  struct OLine {
    OType type = OType::kNone;
    std::string name;          // sub, endsub, call, return: the label; others: "sub#label"
    std::string label;         // as written, for messages
    double test = 0.0;         // while, if, elseif, repeat
    std::vector<double> args;  // call
    int repeats = -1;          // M98 L (-1: none)
    Position at;               // the line's own position
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
    int compensation = kG40;  // G40, G41, G41.1, G42, G42.1
    SpindleDirection spindle = SpindleDirection::kStopped;
    bool mist = false, flood = false;
  };
  struct Frame {
    std::string sub_name;             // empty at the main level
    Position return_to;               // where the caller goes on (kept in the caller's frame)
    std::array<double, 30> saved{};   // the caller's #1-#30
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
  // Loop iterations since the last move: past options_.max_idle_iterations, the loop never ends.
  long idle_iterations_ = 0;
  bool never_ends_ = false;  // the loop limit was hit: reading stops at that error

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
  // Warnings given once per program, later occurrences saying nothing: true the first time.
  std::set<std::string, std::less<>> warned_;
  bool first_warning(std::string_view kind) { return warned_.emplace(kind).second; }
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
  void setup_offsets(const Block& block);           // G10 L2, L20
  void axis_offsets(const Block& block, int code);  // G52, G92, G92.1-G92.3
  void go_home(const Block& block, int code);       // G28, G30
  void warn_machine(const char* what);
  // Canned-cycle memory (LinuxCNC cycle_r, cycle_cc, cycle_p, cycle_q, cycle_il).
  double cycle_r_ = 0.0, cycle_cc_ = 0.0, cycle_p_ = 0.0, cycle_q_ = 0.0;
  bool cycle_initial_level_set_ = false;
  double cycle_initial_level_ = 0.0;
};

}  // namespace cwe::gcode
