#include "envelope_command.hpp"

#include "cli_checks.hpp"

#include <charconv>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/envelope/tangency.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/fcs_svg.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/job/machine.hpp"
#include "cwe/job/tool_choice.hpp"
#include "cwe/job/tool_table.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"

namespace cwe::app {
namespace {

// Most moves written at once without an explicit --moves range.
constexpr int kMostMovesByDefault = 500;

struct MoveRange {
  int first = 1;  // 1-based, inclusive
  int last = 0;
};

std::optional<MoveRange> parse_range(const std::string& text, int count) {
  if (text.empty()) return std::nullopt;
  const auto number = [&](std::string_view s) {
    int value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec != std::errc() || end != s.data() + s.size() || value < 1) {
      throw InputError(SourceLocation{"--moves"},
                       fmt::format("'{}': expected a move number from 1, or a range a-b", text));
    }
    return value;
  };
  const std::size_t dash = text.find('-');
  MoveRange r;
  r.first = number(std::string_view(text).substr(0, dash));
  r.last = dash == std::string::npos ? r.first : number(std::string_view(text).substr(dash + 1));
  if (r.last < r.first || r.last > count) {
    throw InputError(SourceLocation{"--moves"},
                     fmt::format("'{}': the program has moves 1 to {}", text, count));
  }
  return r;
}

// Grazing points grouped into polylines: per patch, one branch per root index, in profile order.
std::vector<std::vector<Vec3>> grazing_polylines(const GrazingCurves& curves) {
  std::map<std::pair<int, int>, std::vector<Vec3>> branches;
  std::size_t i = 0;
  while (i < curves.points.size()) {
    std::size_t j = i;
    while (j < curves.points.size() && curves.points[j].patch == curves.points[i].patch &&
           curves.points[j].u == curves.points[i].u) {
      branches[{curves.points[j].patch, static_cast<int>(j - i)}].push_back(curves.points[j].point);
      ++j;
    }
    i = j;
  }
  std::vector<std::vector<Vec3>> out;
  for (auto& [key, points] : branches) out.push_back(std::move(points));
  return out;
}

}  // namespace

void add_envelope_command(CLI::App& app, EnvelopeCommandOptions& options) {
  CLI::App* cmd = app.add_subcommand(
      "envelope",
      "Swept volumes (STL, PLY), grazing curves (OBJ polylines) and feasible contact "
      "surfaces (SVG) of the feed moves of a toolpath.");
  cmd->add_option("--tool", options.tool,
                  "Tool specification (default: the program's own CUTTER, if it has one)");
  cmd->add_option("--path", options.path, "Toolpath file (G-code or APT CLDATA)")->required();
  cmd->add_option("--moves", options.moves, "Move numbers a-b (1-based, as in 'cwe path --dump')");
  cmd->add_option("--out", options.out, "Output folder")->required();
  cmd->add_option("--subroutine-path", options.subroutine_path,
                  "Folders (':'-separated) searched for G-code subroutine files <name>.ngc");
  cmd->add_option("--machine", options.machine,
                  "Machine definition (JSON: work offsets, G28/G30 positions, travel)");
  cmd->add_option("--tolerance", options.tolerance, "Swept-volume tolerance, mm")
      ->check(positive("a positive length in mm"))
      ->capture_default_str();
  cmd->add_option("--fcs-at", options.fcs_at,
                  "Cutter locations, as move fractions u in [0, 1], at which the feasible contact "
                  "surface is drawn (move-N-fcs-u<U>.svg)")
      ->delimiter(',')
      ->capture_default_str();
}

namespace {

// The feed moves (0-based) of --moves, or of the whole program within the default limit.
std::vector<int> selected_moves(const EnvelopeCommandOptions& options, const Toolpath& path) {
  const int count = static_cast<int>(path.moves.size());
  const std::optional<MoveRange> range = parse_range(options.moves, count);
  std::vector<int> selected;
  for (int i = 0; i < count; ++i) {
    const bool in_range = range ? (i + 1 >= range->first && i + 1 <= range->last) : true;
    if (in_range && !path.moves[static_cast<std::size_t>(i)].is_rapid()) selected.push_back(i);
  }
  if (!range && static_cast<int>(selected.size()) > kMostMovesByDefault) {
    throw InputError(SourceLocation{options.path},
                     fmt::format("{} feed moves: choose at most {} with --moves a-b",
                                 selected.size(), kMostMovesByDefault));
  }
  for (const double u : options.fcs_at) {
    if (!(u >= 0.0 && u <= 1.0)) {
      throw InputError(SourceLocation{"--fcs-at"},
                       fmt::format("{}: expected move fractions between 0 and 1", u));
    }
  }
  return selected;
}

// The files of move i (0-based) added to `files`; its entry of envelope.json returned.
// `previous_x` carries the tool frame's x axis from move to move.
nlohmann::json envelope_of_move(const EnvelopeCommandOptions& options, const Cutter& cutter,
                                const Move& move, int i, Vec3& previous_x,
                                std::map<std::string, std::string>& files) {
  const std::string stem = fmt::format("move-{}", i + 1);
  SweptVolumeOptions sweep_options;
  sweep_options.tolerance = options.tolerance;
  const SweptVolume volume = swept_volume(cutter, move, sweep_options);
  TriangleMesh mesh;
  for (const TriangleMesh& piece : volume.pieces) mesh.append(piece);
  const std::string label = fmt::format("cwe swept volume of move {} (line {})", i + 1, move.line);
  files[stem + ".stl"] = stl_binary(mesh, label);
  files[stem + ".ply"] = ply_ascii(mesh, label);

  std::vector<std::vector<Vec3>> polylines;
  nlohmann::json states = nlohmann::json::array();
  for (const double u : {0.0, 0.5, 1.0}) {
    const ToolState state = tool_state(move, u, previous_x);
    if (u == 0.0) previous_x = state.tcs.x();
    for (auto& p : grazing_polylines(grazing_points(cutter, state)))
      polylines.push_back(std::move(p));
    states.push_back({{"u", u},
                      {"motion", to_string(state.motion)},
                      {"feed_angle_deg", radians_to_degrees(state.feed_angle)}});
  }
  for (const double u : options.fcs_at) {
    const ToolState state = tool_state(move, u, previous_x);
    files[fmt::format("{}-fcs-u{:g}.svg", stem, u)] = fcs_svg(
        cutter, feasible_contact_surface(cutter, state),
        fmt::format(
            "Feasible contact surface, move {} (line {}) at u = {:g}: {}, feed angle {:.1f}°",
            i + 1, move.line, u, to_string(state.motion), radians_to_degrees(state.feed_angle)));
  }
  files[stem + "-grazing.obj"] = obj_polylines(
      polylines, fmt::format("cwe grazing curves of move {} at u = 0, 0.5, 1", i + 1));
  double pieces_volume = 0.0;
  for (const TriangleMesh& piece : volume.pieces) pieces_volume += piece.volume();
  return {{"move", i + 1},
          {"line", move.line},
          {"pieces", volume.pieces.size()},
          {"triangles", mesh.triangles.size()},
          {"volume_mm3",
           volume.pieces.size() == 1 ? nlohmann::json(pieces_volume) : nlohmann::json(nullptr)},
          {"deviation_bound_mm", volume.deviation_bound},
          {"states", states}};
}

}  // namespace

int run_envelope_command(const EnvelopeCommandOptions& options, std::ostream& out) {
  GcodeOptions gcode;
  gcode.subroutine_path = parse_search_path(options.subroutine_path);
  gcode.tool_diameter = compensation_diameters(std::nullopt, options.tool);
  if (!options.machine.empty()) gcode.machine = read_machine_file(options.machine);
  const ReadToolpath read = read_toolpath_file(options.path, gcode);
  const Toolpath& path = read.toolpath;
  const Cutter cutter = choose_cutter(options.tool, SourceLocation{"--tool"}, path, options.path);
  const std::vector<int> selected = selected_moves(options, path);

  // Compute everything first, then write: outputs are whole or absent.
  std::map<std::string, std::string> files;
  nlohmann::json summary;
  summary["tool"] = cutter.name();
  summary["path"] = options.path;
  summary["tolerance_mm"] = options.tolerance;
  summary["moves"] = nlohmann::json::array();
  Vec3 previous_x = Vec3::Zero();
  for (const int i : selected) {
    summary["moves"].push_back(envelope_of_move(
        options, cutter, path.moves[static_cast<std::size_t>(i)], i, previous_x, files));
  }
  files["envelope.json"] = summary.dump(2) + "\n";
  for (const auto& [name, content] : files) {
    write_file_atomically(std::filesystem::path(options.out) / name, content);
  }
  fmt::print(out, "{} feed moves of {} swept with {} (tolerance {:g} mm): {} files in {}\n",
             selected.size(), options.path, cutter.name(), options.tolerance, files.size(),
             options.out);
  fmt::print(out,
             "  move-N.stl / .ply     closed swept volume (one closed shell per linear piece)\n"
             "  move-N-grazing.obj    grazing curves at the start, middle and end (polylines)\n"
             "  move-N-fcs-uU.svg     feasible contact surface at move fraction U (--fcs-at)\n"
             "  envelope.json         per move: pieces, triangles, volume, bound, motion class\n");
  return 0;
}

}  // namespace cwe::app
