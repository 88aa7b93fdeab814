#include "tool_table.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cwe/core/text_file.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe::app {
namespace {

// A tool number as a JSON key: a whole number from 0.
int tool_number(const std::string& key, const SourceLocation& where) {
  int number = 0;
  std::size_t used = 0;
  try {
    number = std::stoi(key, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != key.size() || number < 0) {
    throw InputError(where, fmt::format("\"{}\" is not a tool number; expected a whole number "
                                        "such as \"1\"",
                                        key));
  }
  return number;
}

}  // namespace

ToolTable tool_table_from_json(const nlohmann::json& value, const std::string& source,
                               const std::filesystem::path& folder) {
  const nlohmann::json& entries =
      value.is_object() && value.contains("tools") && value.size() == 1 ? value["tools"] : value;
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
    const nlohmann::json* spec = &entry;
    if (entry.is_object()) {
      for (const auto& [field, unused] : entry.items()) {
        if (field != "spec" && field != "flutes" && field != "helix" && field != "comment") {
          throw InputError(where, fmt::format("unknown key \"{}\"; expected spec, flutes, helix "
                                              "or comment",
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
    }
    if (!spec->is_string() || spec->get<std::string>().empty()) {
      throw InputError(where, "expected a tool specification such as \"flat:10,30\" or a JSON "
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
    table.tools.emplace(number, std::move(tool));
  }
  return table;
}

ToolTable read_tool_table(const std::string& path) {
  const std::string text = read_text_file(path, "tool table");
  nlohmann::json value;
  try {
    value = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(SourceLocation{path}, fmt::format("not valid JSON: {}", e.what()));
  }
  return tool_table_from_json(value, path, std::filesystem::path(path).parent_path());
}

Cutter cutter_of(const ToolEntry& entry) {
  Cutter base = cutter_from_spec(entry.spec, entry.where);
  if (!entry.flutes && !entry.helix_deg) return base;
  CutterOptions options;
  options.name = base.name();
  options.flutes = entry.flutes.value_or(base.flutes());
  options.helix_angle_deg =
      entry.helix_deg.value_or(base.helix_angle() * 180.0 / kPi);
  options.shank = base.shank();
  options.apt = base.apt();
  return Cutter(base.profile(), options);
}

}  // namespace cwe::app
