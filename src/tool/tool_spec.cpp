#include "cwe/tool/tool_spec.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/json_input.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe {
namespace {

constexpr const char* kKnownTypes =
    "flat, ball, bull, taper-flat, taper-ball, chamfer, apt, or a .json tool file";

struct Number {
  double value = 0.0;
  int column = 0;      // 1-based column within the spec
  bool unit = false;   // written with a length unit, "mm" or "in"
  double scale = 1.0;  // mm per unit of the number as written (25.4 for "in")
};

// The location of column `column` (from 1) of a specification that starts at `where` (a string
// given on its own is line 1, column 1).
SourceLocation at(const SourceLocation& where, int column) {
  if (where.line <= 0) return {where.source, 1, column};
  return {where.source, where.line, std::max(where.column, 1) + column - 1};
}

std::vector<Number> parse_numbers(std::string_view text, int first_column,
                                  const SourceLocation& where, double unit = 1.0) {
  std::vector<Number> out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = text.find(',', pos);
    std::string_view item =
        text.substr(pos, comma == std::string_view::npos ? text.npos : comma - pos);
    int column = first_column + static_cast<int>(pos);
    // Allow spaces around values.
    while (!item.empty() && item.front() == ' ') {
      item.remove_prefix(1);
      ++column;
    }
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (item.empty()) throw InputError(at(where, column), "expected a number");
    // A length may carry its unit: 0.375in, 9.525mm.
    Number number;
    number.column = column;
    number.scale = unit;
    for (const auto& [suffix, scale] : {std::pair<std::string_view, double>{"in", 25.4},
                                        std::pair<std::string_view, double>{"mm", 1.0}}) {
      if (item.size() > suffix.size() && item.substr(item.size() - suffix.size()) == suffix) {
        item.remove_suffix(suffix.size());
        number.unit = true;
        number.scale = scale;
        break;
      }
    }
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), number.value);
    if (ec != std::errc() || end != item.data() + item.size() || !std::isfinite(number.value)) {
      throw InputError(at(where, column), fmt::format("expected a number, found '{}'", item));
    }
    if (std::abs(number.value * number.scale) > kLargestInputValue) {
      throw InputError(at(where, column),
                       fmt::format("'{}' is beyond the largest value cwe takes ({:g})", item,
                                   kLargestInputValue));
    }
    out.push_back(number);
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return out;
}

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

Cutter cutter_from_apt(const AptCutter& apt, CutterOptions options, const SourceLocation& where) {
  Profile profile = apt_profile(apt, where);
  options.apt = apt;
  return Cutter(std::move(profile), std::move(options));
}

// Builds the APT parameters of a "type:values" specification.
AptCutter apt_from_spec(std::string_view type, const std::vector<Number>& v,
                        const SourceLocation& where, int type_column) {
  const auto arity = [&](std::size_t lo, std::size_t hi, const char* form) {
    if (v.size() < lo || v.size() > hi) {
      throw InputError(at(where, type_column),
                       fmt::format("'{}' takes {} ({} value{} given)", type, form, v.size(),
                                   v.size() == 1 ? "" : "s"));
    }
  };
  // Lengths in mm unless written in inches; angles in degrees, without a unit.
  const auto value = [&](std::size_t i) { return i < v.size() ? v[i].value * v[i].scale : 0.0; };
  const auto loc = [&](std::size_t i) { return at(where, v[std::min(i, v.size() - 1)].column); };
  const auto angle = [&](std::size_t i) {
    if (i < v.size() && v[i].unit) {
      throw InputError(at(where, v[i].column), "an angle in degrees takes no length unit");
    }
    return i < v.size() ? v[i].value : 0.0;
  };
  // The flute height h, last of each form: written, it must be positive (left out: the default).
  const auto height = [&](std::size_t i) {
    if (i < v.size() && !(value(i) > 0.0)) {
      throw InputError(at(where, v[i].column),
                       fmt::format("h = {:g}: the height must be positive (leave it out for the "
                                   "default)",
                                   value(i)));
    }
    return value(i);
  };
  if (type == "flat") {
    arity(1, 2, "D[,h]");
    return flat_end_mill(value(0), height(1), loc(0));
  }
  if (type == "ball") {
    arity(1, 2, "D[,h]");
    return ball_end_mill(value(0), height(1), loc(0));
  }
  if (type == "bull") {
    arity(2, 3, "D,r[,h]");
    return bull_nose_end_mill(value(0), value(1), height(2), loc(1));
  }
  if (type == "taper-flat") {
    arity(2, 3, "D,beta_deg[,h]");
    return taper_flat_end_mill(value(0), angle(1), height(2), loc(1));
  }
  if (type == "taper-ball") {
    arity(2, 3, "D,beta_deg[,h]");
    return taper_ball_end_mill(value(0), angle(1), height(2), loc(1));
  }
  if (type == "chamfer") {
    arity(2, 3, "D,tip_angle_deg[,h]");
    return chamfer_mill(value(0), angle(1), height(2), loc(1));
  }
  if (type == "apt") {
    arity(1, 7, "d[,r[,e,f[,alpha_deg,beta_deg[,h]]]]");
    std::vector<double> values(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) values[i] = i == 4 || i == 5 ? angle(i) : value(i);
    return apt_from_values(values, loc(0));
  }
  throw InputError(at(where, type_column),
                   fmt::format("unknown tool type '{}' (expected {})", type, kKnownTypes));
}

double json_number(const nlohmann::json& j, const std::string& what, const std::string& source) {
  if (!j.is_number()) {
    throw InputError(SourceLocation{source},
                     fmt::format("{}: expected a number, found {}", what, j.dump()));
  }
  const double value = j.get<double>();
  if (std::abs(value) > kLargestInputValue) {
    throw InputError(SourceLocation{source},
                     fmt::format("{}: {} is beyond the largest value cwe takes ({:g})", what,
                                 j.dump(), kLargestInputValue));
  }
  return value;
}

Vec2 json_point(const nlohmann::json& j, const std::string& what, const std::string& source) {
  if (!j.is_array() || j.size() != 2) {
    throw InputError(SourceLocation{source},
                     fmt::format("{}: expected a point [radius, z], found {}", what, j.dump()));
  }
  return {json_number(j[0], what, source), json_number(j[1], what, source)};
}

Profile json_profile(const nlohmann::json& pieces, const std::string& source) {
  if (!pieces.is_array() || pieces.empty()) {
    throw InputError(SourceLocation{source}, "\"profile\": expected a non-empty array of pieces");
  }
  std::vector<ProfileSegment> segments;
  Vec2 from = Vec2::Zero();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const auto& p = pieces[i];
    const std::string what = fmt::format("\"profile\" piece {}", i + 1);
    if (!p.is_object()) {
      throw InputError(SourceLocation{source}, what +
                                                   ": expected {\"line\": [r, z]} or {\"arc\": [r, "
                                                   "z], \"center\": [r, z], \"ccw\": true}");
    }
    for (const auto& [key, unused] : p.items()) {
      if (key != "line" && key != "arc" && key != "center" && key != "ccw") {
        throw InputError(SourceLocation{source}, fmt::format("{}: unknown key \"{}\"", what, key));
      }
    }
    if (p.contains("line") == p.contains("arc")) {
      throw InputError(SourceLocation{source}, what + ": give exactly one of \"line\" and \"arc\"");
    }
    if (p.contains("line")) {
      const Vec2 to = json_point(p["line"], what, source);
      segments.push_back(ProfileSegment::line(from, to));
      from = to;
    } else {
      if (!p.contains("center"))
        throw InputError(SourceLocation{source}, what + ": an arc needs \"center\"");
      const Vec2 to = json_point(p["arc"], what, source);
      const Vec2 center = json_point(p["center"], what + " centre", source);
      bool ccw = true;
      if (p.contains("ccw")) {
        if (!p["ccw"].is_boolean())
          throw InputError(SourceLocation{source}, what + ": \"ccw\" must be true or false");
        ccw = p["ccw"].get<bool>();
      }
      segments.push_back(ProfileSegment::arc(from, to, center, ccw));
      from = to;
    }
  }
  return Profile(std::move(segments), source);
}

}  // namespace

Cutter cutter_from_spec(std::string_view spec, const SourceLocation& where, double unit) {
  if (ends_with(spec, ".json")) return cutter_from_file(std::string(spec));
  const std::size_t colon = spec.find(':');
  if (colon == std::string_view::npos) {
    throw InputError(
        at(where, 1),
        fmt::format("'{}' is not a tool specification: expected type:values, one of {}", spec,
                    kKnownTypes));
  }
  const std::string_view type = spec.substr(0, colon);
  const std::vector<Number> numbers =
      parse_numbers(spec.substr(colon + 1), static_cast<int>(colon) + 2, where, unit);
  const AptCutter apt = apt_from_spec(type, numbers, where, 1);
  CutterOptions options;
  options.name = std::string(spec);
  return cutter_from_apt(apt, std::move(options), at(where, 1));
}

Cutter cutter_from_file(const std::string& path) {
  return cutter_from_json(read_text_file(path, "tool file"), path);
}

namespace {

Cutter cutter_from_json_object(std::string_view text, const std::string& source);

}  // namespace

Cutter cutter_from_json(std::string_view text, const std::string& source) {
  try {
    return cutter_from_json_object(text, source);
  } catch (const InputError& e) {
    // The cutter's own checks name the tool ("tool" when unnamed): here the file is known.
    if (e.location().line > 0 || e.location().source.starts_with(source)) throw;
    throw InputError(SourceLocation{source}, e.message());
  }
}

namespace {

Cutter cutter_from_json_object(std::string_view text, const std::string& source) {
  const nlohmann::json j = parse_json_input(text, source);
  if (!j.is_object())
    throw InputError(SourceLocation{source}, "a tool file must hold a JSON object");
  for (const auto& [key, unused] : j.items()) {
    if (key != "name" && key != "spec" && key != "apt" && key != "profile" && key != "flutes" &&
        key != "helix_deg" && key != "shank") {
      throw InputError(SourceLocation{source},
                       fmt::format("unknown key \"{}\" (expected name, spec, apt, profile, "
                                   "flutes, helix_deg, shank)",
                                   key));
    }
  }
  const int forms = static_cast<int>(j.contains("spec")) + static_cast<int>(j.contains("apt")) +
                    static_cast<int>(j.contains("profile"));
  if (forms != 1) {
    throw InputError(SourceLocation{source},
                     "give exactly one of \"spec\", \"apt\" and \"profile\" to define the shape");
  }

  CutterOptions options;
  options.name = source;
  if (j.contains("name")) {
    if (!j["name"].is_string())
      throw InputError(SourceLocation{source}, "\"name\" must be a string");
    options.name = j["name"].get<std::string>();
  }
  if (j.contains("flutes")) {
    const double n = json_number(j["flutes"], "\"flutes\"", source);
    if (n != std::floor(n) || n < 1 || n > 100) {
      throw InputError(
          SourceLocation{source},
          fmt::format("\"flutes\": expected a whole number from 1 to 100, found {}", n));
    }
    options.flutes = static_cast<int>(n);
  }
  if (j.contains("helix_deg"))
    options.helix_angle_deg = json_number(j["helix_deg"], "\"helix_deg\"", source);
  if (j.contains("shank")) {
    const auto& s = j["shank"];
    if (!s.is_object() || !s.contains("diameter") || !s.contains("length") || s.size() != 2) {
      throw InputError(SourceLocation{source},
                       "\"shank\": expected {\"diameter\": mm, \"length\": mm}");
    }
    options.shank = Shank{json_number(s["diameter"], "shank diameter", source),
                          json_number(s["length"], "shank length", source)};
  }

  const SourceLocation where{source};
  if (j.contains("profile")) return Cutter(json_profile(j["profile"], source), std::move(options));
  AptCutter apt;
  if (j.contains("apt")) {
    const auto& a = j["apt"];
    if (!a.is_array()) throw InputError(where, "\"apt\": expected an array of 1 to 7 numbers");
    std::vector<double> values;
    for (const auto& v : a) values.push_back(json_number(v, "\"apt\"", source));
    apt = apt_from_values(values, where);
  } else {
    if (!j["spec"].is_string())
      throw InputError(where, "\"spec\" must be a string such as \"flat:10\"");
    const std::string spec = j["spec"].get<std::string>();
    if (ends_with(spec, ".json")) throw InputError(where, "\"spec\" cannot name another tool file");
    const std::size_t colon = spec.find(':');
    if (colon == std::string::npos) {
      throw InputError(where,
                       fmt::format("\"spec\": '{}' is not type:values ({})", spec, kKnownTypes));
    }
    const SourceLocation in_spec{source + " (\"spec\")"};
    apt = apt_from_spec(std::string_view(spec).substr(0, colon),
                        parse_numbers(std::string_view(spec).substr(colon + 1),
                                      static_cast<int>(colon) + 2, in_spec),
                        in_spec, 1);
  }
  return cutter_from_apt(apt, std::move(options), where);
}

}  // namespace

}  // namespace cwe
