#include "tool_command.hpp"

#include <cctype>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/profile_svg.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe::app {
namespace {

std::string describe_segment(const ProfileSegment& s) {
  if (s.kind == ProfileSegment::Kind::kLine) {
    return fmt::format("line ({:.4g}, {:.4g}) -> ({:.4g}, {:.4g})", s.start.x(), s.start.y(),
                       s.end.x(), s.end.y());
  }
  return fmt::format(
      "arc  ({:.4g}, {:.4g}) -> ({:.4g}, {:.4g}) centre ({:.4g}, {:.4g}) radius {:.4g} {}",
      s.start.x(), s.start.y(), s.end.x(), s.end.y(), s.center.x(), s.center.y(), s.radius,
      s.counterclockwise ? "ccw" : "cw");
}

void print_text(const Cutter& c, std::ostream& out) {
  fmt::print(out, "Tool {}\n", c.name());
  if (c.apt()) fmt::print(out, "  APT form        {}\n", to_string(*c.apt()));
  fmt::print(out, "  diameter        {:.6g} mm\n", c.diameter());
  fmt::print(out, "  cutting length  {:.6g} mm\n", c.flute_length());
  fmt::print(out, "  top diameter    {:.6g} mm\n", 2.0 * c.profile().top_radius());
  fmt::print(out, "  flutes          {}, helix {:.6g} deg\n", c.flutes(),
             radians_to_degrees(c.helix_angle()));
  fmt::print(out, "  shank           diameter {:.6g} mm, length {:.6g} mm\n", c.shank().diameter,
             c.shank().length);
  fmt::print(out, "Profile (radius, height in mm, from the tip up):\n");
  for (std::size_t i = 0; i < c.profile().segments().size(); ++i) {
    fmt::print(out, "  {}  {}\n", i + 1, describe_segment(c.profile().segments()[i]));
  }
  fmt::print(out, "Patches (surfaces of revolution; z = height above the tip):\n");
  for (std::size_t i = 0; i < c.patches().size(); ++i) {
    const CutterPatch& p = c.patches()[i];
    fmt::print(out, "  {}  {:<12} radius <= {:<8.4g} z {:.4g} .. {:.4g}\n", i + 1,
               to_string(p.kind), p.bounds.radius, p.bounds.z_min, p.bounds.z_max);
  }
}

nlohmann::json to_json(const Cutter& c) {
  nlohmann::json j;
  j["name"] = c.name();
  if (c.apt()) {
    const AptCutter& a = *c.apt();
    j["apt"] = {a.d, a.r, a.e, a.f, a.alpha_deg, a.beta_deg, a.h};
  }
  j["diameter_mm"] = c.diameter();
  j["cutting_length_mm"] = c.flute_length();
  j["flutes"] = c.flutes();
  j["helix_deg"] = radians_to_degrees(c.helix_angle());
  j["shank"] = {{"diameter_mm", c.shank().diameter}, {"length_mm", c.shank().length}};
  nlohmann::json profile = nlohmann::json::array();
  for (const ProfileSegment& s : c.profile().segments()) {
    nlohmann::json piece;
    if (s.kind == ProfileSegment::Kind::kLine) {
      piece["line"] = {s.end.x(), s.end.y()};
    } else {
      piece["arc"] = {s.end.x(), s.end.y()};
      piece["center"] = {s.center.x(), s.center.y()};
      piece["ccw"] = s.counterclockwise;
    }
    profile.push_back(piece);
  }
  j["profile"] = profile;
  nlohmann::json patches = nlohmann::json::array();
  for (const CutterPatch& p : c.patches()) {
    patches.push_back({{"kind", to_string(p.kind)},
                       {"radius_mm", p.bounds.radius},
                       {"z_min_mm", p.bounds.z_min},
                       {"z_max_mm", p.bounds.z_max}});
  }
  j["patches"] = patches;
  return j;
}

// A file name from a specification: "bull:10,2" -> "bull-10-2".
std::string file_stem(const std::string& spec) {
  const std::filesystem::path path(spec);
  std::string stem = path.extension() == ".json" ? path.stem().string() : spec;
  for (char& ch : stem) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '.' && ch != '-') ch = '-';
  }
  return stem;
}

}  // namespace

void add_tool_command(CLI::App& app, ToolCommandOptions& options) {
  CLI::App* tool = app.add_subcommand(
      "tool", "Describe cutters: profile pieces, surface patches, key dimensions; draw them.");
  tool->add_option("spec", options.specs,
                   "Tool specifications (flat:D[,h], ball:D[,h], bull:D,r[,h], "
                   "taper-flat:D,beta[,h], taper-ball:D,beta[,h], chamfer:D,tip[,h], "
                   "apt:d,r,e,f,alpha,beta,h, or a .json tool file)")
      ->required();
  tool->add_option("--svg", options.svg_file, "Write the profile drawing of the (single) tool");
  tool->add_option("--svg-dir", options.svg_dir, "Write one drawing per tool into this folder");
  tool->add_flag("--json", options.json, "Print a JSON object per tool instead of text");
}

int run_tool_command(const ToolCommandOptions& options, std::ostream& out) {
  if (!options.svg_file.empty() && options.specs.size() != 1) {
    throw InputError(SourceLocation{"--svg"}, "draws one tool; use --svg-dir for several");
  }
  // Parse everything first: a bad specification writes nothing.
  std::vector<Cutter> cutters;
  for (const std::string& spec : options.specs) cutters.push_back(cutter_from_spec(spec));

  for (std::size_t i = 0; i < cutters.size(); ++i) {
    if (options.json) {
      out << to_json(cutters[i]).dump() << '\n';
    } else {
      if (i > 0) out << '\n';
      print_text(cutters[i], out);
    }
  }
  if (!options.svg_file.empty()) write_file_atomically(options.svg_file, profile_svg(cutters[0]));
  if (!options.svg_dir.empty()) {
    for (std::size_t i = 0; i < cutters.size(); ++i) {
      const auto path = std::filesystem::path(options.svg_dir) /
                        fmt::format("{:02}-{}.svg", i + 1, file_stem(options.specs[i]));
      write_file_atomically(path, profile_svg(cutters[i]));
      if (!options.json) fmt::print(out, "wrote {}\n", path.string());
    }
  }
  return 0;
}

}  // namespace cwe::app
