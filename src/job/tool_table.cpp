#include "cwe/job/tool_table.hpp"

#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cwe/core/json_input.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/process/cutting_coefficients.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe {
namespace {

// The number at the start of `text` (as std::stod reads it): the characters it takes, 0 when
// there is none or it is not finite.
std::size_t leading_number(const std::string& text, double& value) {
  std::size_t used = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return 0;
  }
  return std::isfinite(value) ? used : 0;
}

// A tool number as a JSON key: a whole number from 0.
int tool_number(const std::string& key, const SourceLocation& where) {
  double value = 0.0;
  const std::size_t used = leading_number(key, value);
  const int number = value >= 0.0 && value <= 1e9 ? static_cast<int>(value) : -1;
  if (used == 0 || used != key.size() || number < 0 || number != value) {
    throw InputError(where, fmt::format("\"{}\" is not a tool number; expected a whole number "
                                        "such as \"1\"",
                                        key));
  }
  return number;
}

}  // namespace

ToolTable tool_table_from_json(const nlohmann::json& value, const std::string& source,
                               const std::filesystem::path& folder, double unit) {
  // {"tools": {…}} (with an optional "comment"), or the entries themselves.
  const bool wrapped = value.is_object() && value.contains("tools");
  if (wrapped) {
    for (const auto& [key, unused] : value.items()) {
      if (key != "tools" && key != "comment") {
        throw InputError(SourceLocation{source},
                         fmt::format("unknown key \"{}\"; expected tools or comment", key));
      }
    }
  }
  const nlohmann::json& entries = wrapped ? value["tools"] : value;
  if (!entries.is_object() || entries.empty()) {
    throw InputError(SourceLocation{source},
                     "expected a tool table: {\"1\": \"flat:10,30\", \"2\": …} by tool number");
  }
  ToolTable table;
  table.source = source;
  for (const auto& [key, entry] : entries.items()) {
    const SourceLocation where{fmt::format("{}: tool \"{}\"", source, key)};
    ToolEntry tool;
    tool.where = where;
    tool.unit = unit;
    const nlohmann::json* spec = &entry;
    if (entry.is_object()) {
      for (const auto& [field, unused] : entry.items()) {
        if (field != "spec" && field != "flutes" && field != "helix" && field != "forces" &&
            field != "comment") {
          throw InputError(where, fmt::format("unknown key \"{}\"; expected spec, flutes, helix, "
                                              "forces or comment",
                                              field));
        }
      }
      if (!entry.contains("spec")) throw InputError(where, "expected \"spec\": a tool");
      spec = &entry["spec"];
      if (entry.contains("flutes")) {
        const nlohmann::json& f = entry["flutes"];
        if (!f.is_number_integer() || f.get<long long>() < 1 || f.get<long long>() > 64) {
          throw InputError(where, "\"flutes\": expected a whole number from 1 to 64");
        }
        tool.flutes = f.get<int>();
      }
      if (entry.contains("helix")) {
        const nlohmann::json& h = entry["helix"];
        if (!h.is_number() || !std::isfinite(h.get<double>()) || h.get<double>() < 0.0 ||
            h.get<double>() >= 90.0) {
          throw InputError(where, "\"helix\": expected an angle in degrees from 0 to below 90");
        }
        tool.helix_deg = h.get<double>();
      }
      if (entry.contains("forces")) {
        const nlohmann::json& f = entry["forces"];
        if (!f.is_string() || f.get<std::string>().empty()) {
          throw InputError(where,
                           "\"forces\": expected a coefficient JSON file or a bundled "
                           "material (cwe materials lists them)");
        }
        std::string name = f.get<std::string>();
        if ((name.ends_with(".json") || name.find('/') != std::string::npos) &&
            std::filesystem::path(name).is_relative()) {
          name = (folder / name).lexically_normal().string();
        }
        try {
          tool.coefficients = load_cutting_coefficients(name);
        } catch (const InputError& e) {
          throw InputError(where, fmt::format("\"forces\": {}", e.what()));
        }
      }
    }
    if (!spec->is_string() || spec->get<std::string>().empty()) {
      throw InputError(where,
                       "expected a tool specification such as \"flat:10,30\" or a JSON "
                       "tool file");
    }
    tool.spec = spec->get<std::string>();
    if (tool.spec.size() > 5 && tool.spec.ends_with(".json") &&
        std::filesystem::path(tool.spec).is_relative()) {
      tool.spec = (folder / tool.spec).lexically_normal().string();
    }
    const int number = tool_number(key, where);
    // Each entry is checked now, before any long run.
    (void)cutter_of(tool);
    if (!table.tools.emplace(number, std::move(tool)).second) {
      throw InputError(where,
                       fmt::format("tool {} is listed twice (as \"{}\" and before)", number, key));
    }
  }
  return table;
}

namespace {

nlohmann::json read_json(const std::string& path, const char* what) {
  return parse_json_input(read_text_file(path, what), path);
}

// A FreeCAD quantity, "6.0000 mm", "0.2500 in", "119.0000 °" or a bare number, in mm or degrees.
double quantity(const nlohmann::json& value, const SourceLocation& where, bool angle) {
  if (value.is_number()) return value.get<double>();
  if (!value.is_string()) throw InputError(where, "expected a quantity such as \"6.0000 mm\"");
  const std::string text = value.get<std::string>();
  double number = 0.0;
  const std::size_t used = leading_number(text, number);
  std::string unit = text.substr(used);
  unit.erase(0, unit.find_first_not_of(' '));
  unit.erase(unit.find_last_not_of(' ') + 1);
  double scale = 0.0;
  if (angle && (unit == "\u00b0" || unit == "deg" || unit.empty())) scale = 1.0;
  if (!angle && (unit == "mm" || unit.empty())) scale = 1.0;
  if (!angle && (unit == "in" || unit == "\"")) scale = 25.4;
  if (!angle && unit == "cm") scale = 10.0;
  if (!angle && unit == "m") scale = 1000.0;
  if (used == 0 || scale == 0.0 || number < 0.0) {
    throw InputError(where, fmt::format("\"{}\" is not a {}", text,
                                        angle ? "angle in degrees (\"60.0000 °\")"
                                              : "length (\"6.0000 mm\", \"0.2500 in\")"));
  }
  return number * scale;
}

// The parameters of a FreeCAD tool bit, read as lengths (mm) or angles (degrees).
struct BitParameters {
  const std::string& path;
  const nlohmann::json& p;
  std::optional<double> get(const char* key, bool angle) const {
    if (!p.contains(key)) return std::nullopt;
    return quantity(p[key], SourceLocation{fmt::format("{}: \"{}\"", path, key)}, angle);
  }
  std::optional<double> length(const char* key) const { return get(key, false); }
  std::optional<double> angle(const char* key) const { return get(key, true); }
};

// A chamfer or v-bit as a cwe profile tool: a cone from the flat tip (TipDiameter) at half the
// CuttingEdgeAngle from the axis, as FreeCAD's shapes draw it. A chamfer mill's cone is
// CuttingEdgeHeight tall (its Diameter is not its geometry), a v-bit's rises to its Diameter.
std::string cone_bit_json(const nlohmann::json& bit, const std::string& shape,
                          const BitParameters& p, double diameter, std::optional<double> height) {
  const SourceLocation where{p.path};
  const std::optional<double> included = p.angle("CuttingEdgeAngle");
  if (!included || !(*included > 0.0 && *included < 180.0)) {
    throw InputError(where, fmt::format("the {} bit needs a \"CuttingEdgeAngle\" between 0° "
                                        "and 180°",
                                        shape));
  }
  const double slope = std::tan(*included * kPi / 360.0);
  const double tip = 0.5 * p.length("TipDiameter").value_or(0.0);
  double top = 0.0;
  if (shape == "chamfer") {
    if (!height || !(*height > 0.0)) {
      throw InputError(where, "the chamfer bit needs a positive \"CuttingEdgeHeight\"");
    }
    top = tip + *height * slope;
  } else {
    top = 0.5 * diameter;
    if (!(top > tip)) throw InputError(where, "the v-bit's Diameter is not above its tip");
    height = (top - tip) / slope;
  }
  const std::string name = bit.contains("name") && bit["name"].is_string()
                               ? bit["name"].get<std::string>()
                               : std::filesystem::path(p.path).stem().string();
  nlohmann::json profile = nlohmann::json::array();
  if (tip > 0.0) profile.push_back({{"line", {tip, 0.0}}});
  profile.push_back({{"line", {top, *height}}});
  return nlohmann::json{{"name", fmt::format("{} (FreeCAD {})", name, shape)}, {"profile", profile}}
      .dump();
}

// Flutes, where FreeCAD 1.0 keeps them (0 if absent or not a whole count from 1 to 64).
int freecad_flutes(const nlohmann::json& bit, const SourceLocation& where) {
  int count = 0;
  for (const char* group : {"parameter", "attribute"}) {
    if (bit.contains(group) && bit[group].is_object() && bit[group].contains("Flutes")) {
      const nlohmann::json& f = bit[group]["Flutes"];
      const double flutes = f.is_number() ? f.get<double>() : quantity(f, where, true);
      if (flutes >= 1.0 && flutes <= 64.0 && flutes == std::floor(flutes)) {
        count = static_cast<int>(flutes);
      }
    }
  }
  return count;
}

// The cwe entry of a FreeCAD tool bit (.fctb): the shape's parameters as a tool specification.
ToolEntry freecad_bit(const std::string& path) {
  const nlohmann::json bit = read_json(path, "FreeCAD tool bit");
  const SourceLocation where{path};
  if (!bit.is_object() || !bit.contains("shape") || !bit["shape"].is_string() ||
      !bit.contains("parameter") || !bit["parameter"].is_object()) {
    throw InputError(where, "expected a FreeCAD tool bit: {\"shape\": …, \"parameter\": {…}}");
  }
  const std::string shape = std::filesystem::path(bit["shape"].get<std::string>()).stem().string();
  const BitParameters p{path, bit["parameter"]};
  const std::optional<double> diameter = p.length("Diameter");
  if (!diameter || !(*diameter > 0.0)) {
    throw InputError(where, fmt::format("the {} bit has no positive \"Diameter\"", shape));
  }
  // The cutting length: the cutting edge's height, else (drills) the whole length.
  std::optional<double> height = p.length("CuttingEdgeHeight");
  const auto suffix = [&] { return height ? fmt::format(",{:.6g}", *height) : std::string(); };
  ToolEntry entry;
  entry.where = where;
  if (shape == "endmill") {
    entry.spec = fmt::format("flat:{:.6g}{}", *diameter, suffix());
  } else if (shape == "ballend") {
    entry.spec = fmt::format("ball:{:.6g}{}", *diameter, suffix());
  } else if (shape == "bullnose" || shape == "torus") {
    std::optional<double> corner = p.length("CornerRadius");
    if (!corner) corner = p.length("TorusRadius");
    if (!corner) {
      const std::optional<double> flat = p.length("FlatRadius");
      if (flat) corner = 0.5 * *diameter - *flat;
    }
    if (!corner) throw InputError(where, "the bull nose bit has no \"FlatRadius\"");
    entry.spec = fmt::format("bull:{:.6g},{:.6g}{}", *diameter, *corner, suffix());
  } else if (shape == "drill") {
    const std::optional<double> tip = p.angle("TipAngle");
    if (!tip) throw InputError(where, "the drill bit has no \"TipAngle\"");
    if (!height) height = p.length("Length");
    entry.spec = fmt::format("chamfer:{:.6g},{:.6g}{}", *diameter, *tip, suffix());
  } else if (shape == "chamfer" || shape == "v-bit") {
    entry.json = cone_bit_json(bit, shape, p, *diameter, height);
  } else {
    throw InputError(where,
                     fmt::format("a FreeCAD \"{}\" bit: cwe reads endmill, ballend, bullnose, "
                                 "torus, drill, chamfer and v-bit bits; give this tool as a "
                                 "specification or a profile tool file (cwe tool --help) in a cwe "
                                 "tool table",
                                 shape));
  }
  if (const int flutes = freecad_flutes(bit, where); flutes > 0) entry.flutes = flutes;
  return entry;
}

// A FreeCAD tool library (.fctl): {"tools": [{"nr": 1, "path": "5mm_Endmill.fctb"}, …]}. Bits
// are found beside the library or in the Bit folder next to it (FreeCAD's Tools/ layout).
ToolTable freecad_library(const std::string& path) {
  const nlohmann::json library = read_json(path, "FreeCAD tool library");
  if (!library.is_object() || !library.contains("tools") || !library["tools"].is_array()) {
    throw InputError(SourceLocation{path},
                     "expected a FreeCAD tool library: {\"tools\": [{\"nr\": 1, \"path\": …}]}");
  }
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  ToolTable table;
  table.source = path;
  for (std::size_t k = 0; k < library["tools"].size(); ++k) {
    const nlohmann::json& tool = library["tools"][k];
    const SourceLocation where{fmt::format("{}: \"tools\"[{}]", path, k)};
    if (!tool.is_object() || !tool.contains("nr") || !tool["nr"].is_number_integer() ||
        tool["nr"].get<long long>() < 0 || tool["nr"].get<long long>() > 1000000000 ||
        !tool.contains("path") || !tool["path"].is_string()) {
      throw InputError(where, "expected {\"nr\": a tool number, \"path\": a .fctb file}");
    }
    const std::filesystem::path bit(tool["path"].get<std::string>());
    std::filesystem::path found = bit.is_absolute() ? bit : folder / bit;
    if (!std::filesystem::exists(found) && !bit.is_absolute()) {
      found = folder / ".." / "Bit" / bit;
    }
    if (!std::filesystem::exists(found)) {
      throw InputError(where, fmt::format("tool bit {} not found beside the library or in ../Bit",
                                          bit.string()));
    }
    // A bit cwe cannot read or model (FreeCAD's default library has a probe and a slitting saw)
    // is an error only for a program that loads it.
    ToolEntry entry;
    try {
      entry = freecad_bit(found.lexically_normal().string());
      (void)cutter_of(entry);
    } catch (const InputError& e) {
      entry.where = SourceLocation{found.lexically_normal().string()};
      entry.refused = e.message();
    }
    if (!table.tools.emplace(tool["nr"].get<int>(), std::move(entry)).second) {
      throw InputError(SourceLocation{path},
                       fmt::format("tool {} is listed twice", tool["nr"].get<int>()));
    }
  }
  if (table.tools.empty()) throw InputError(SourceLocation{path}, "the library holds no tools");
  return table;
}

// A LinuxCNC tool table (tool.tbl): one tool a line, "T1 P1 Z+25.0 D6.0 ;comment", lengths in
// the machine's units. The comment may name the cutter, "cwe:ball:6,25" (a specification in mm);
// without it a tool is a flat end mill of diameter D.
ToolTable linuxcnc_table(const std::string& path, bool inches) {
  const std::string text = read_text_file(path, "LinuxCNC tool table");
  ToolTable table;
  table.source = path;
  std::size_t start = 0;
  for (int line = 1; start < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    std::string row = text.substr(start, end - start);
    start = end + 1;
    if (!row.empty() && row.back() == '\r') row.pop_back();
    std::string comment;
    std::size_t comment_at = 0;  // the comment's offset in the line
    if (const std::size_t semi = row.find(';'); semi != std::string::npos) {
      comment = row.substr(semi + 1);
      comment_at = semi + 1;
      row.resize(semi);
    }
    std::optional<int> number;
    double diameter = 0.0;
    for (std::size_t k = 0; k < row.size();) {
      if (row[k] == ' ' || row[k] == '\t') {
        ++k;
        continue;
      }
      const SourceLocation at{path, line, static_cast<int>(k) + 1};
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(row[k])));
      if (std::string_view("TPXYZABCUVWDIJQ").find(letter) == std::string_view::npos) {
        throw InputError(at, fmt::format("'{}' is not a tool table word; expected T, P, X, Y, Z, "
                                         "A, B, C, U, V, W, D, I, J or Q",
                                         row[k]));
      }
      double value = 0.0;
      const std::size_t used = leading_number(row.substr(k + 1), value);
      if (used == 0) {
        throw InputError(at, fmt::format("{} needs a number", letter));
      }
      if (letter == 'T') {
        if (value < 0.0 || value != std::floor(value) || value > 1e9) {
          throw InputError(at, "T needs a whole tool number");
        }
        number = static_cast<int>(value);
      }
      if (letter == 'D') {
        if (!(value > 0.0) || value > 1e6) {
          throw InputError(at, fmt::format("D{:g}: expected a positive diameter", value));
        }
        diameter = value * (inches ? 25.4 : 1.0);
      }
      k += 1 + used;
    }
    if (!number) {
      if (row.find_first_not_of(" \t") != std::string::npos) {
        throw InputError(SourceLocation{path, line, 1}, "a tool line needs its T number");
      }
      continue;  // a blank or comment line
    }
    ToolEntry entry;
    entry.where = SourceLocation{path, line, 1};
    if (const std::size_t key = comment.find("cwe:"); key != std::string::npos) {
      const std::size_t from = key + 4;
      const std::size_t to = comment.find_first_of(" \t", from);
      entry.spec = comment.substr(from, to == std::string::npos ? std::string::npos : to - from);
      entry.where.column = static_cast<int>(comment_at + from) + 1;  // the spec's own column
    } else if (diameter > 0.0) {
      entry.spec = fmt::format("flat:{:.6g}", diameter);
    } else {
      entry.refused =
          fmt::format("tool {} has no diameter (D) and no cwe: key in its comment", *number);
    }
    if (entry.refused.empty()) (void)cutter_of(entry);
    if (!table.tools.emplace(*number, std::move(entry)).second) {
      throw InputError(SourceLocation{path, line, 1},
                       fmt::format("tool {} is listed twice", *number));
    }
  }
  if (table.tools.empty()) throw InputError(SourceLocation{path}, "the table lists no tools");
  return table;
}

}  // namespace

ToolTable read_tool_table(const std::string& path, bool inches) {
  if (path.ends_with(".fctl")) return freecad_library(path);
  if (path.ends_with(".tbl")) return linuxcnc_table(path, inches);
  return tool_table_from_json(read_json(path, "tool table"), path,
                              std::filesystem::path(path).parent_path(),
                              inches ? kMillimetresPerInch : 1.0);
}

Cutter cutter_of(const ToolEntry& entry) {
  if (!entry.refused.empty()) throw InputError(entry.where, entry.refused);
  Cutter base = entry.json.empty() ? cutter_from_spec(entry.spec, entry.where, entry.unit)
                                   : cutter_from_json(entry.json, entry.where.source);
  if (!entry.flutes && !entry.helix_deg) return base;
  CutterOptions options;
  options.name = base.name();
  options.flutes = entry.flutes.value_or(base.flutes());
  options.helix_angle_deg = entry.helix_deg.value_or(base.helix_angle() * 180.0 / kPi);
  options.shank = base.shank();
  options.apt = base.apt();
  return Cutter(base.profile(), options);
}

double compensation_diameter(const Cutter& cutter) {
  return cutter.apt() ? cutter.apt()->d : cutter.diameter();
}

std::function<std::optional<double>(int tool)> compensation_diameters(
    const std::optional<ToolTable>& table, const std::string& tool_spec, double unit,
    const SourceLocation& tool_at) {
  if (!tool_spec.empty()) {
    const double d = compensation_diameter(cutter_from_spec(tool_spec, tool_at, unit));
    return [d](int) { return std::optional<double>(d); };
  }
  if (!table) return {};
  // Each tool's cutter is made once, when a program first compensates with it.
  auto known = std::make_shared<std::map<int, double>>();
  return [tools = table->tools, known](int tool) -> std::optional<double> {
    if (const auto k = known->find(tool); k != known->end()) return k->second;
    const auto entry = tools.find(tool);
    if (entry == tools.end()) return std::nullopt;
    const double d = compensation_diameter(cutter_of(entry->second));
    known->emplace(tool, d);
    return d;
  };
}

}  // namespace cwe
