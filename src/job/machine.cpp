#include "cwe/job/machine.hpp"

#include <array>
#include <cmath>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/json_input.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe {
namespace {

// G54 … G59 are systems 1 … 6, G59.1 … G59.3 are 7 … 9; 0 for another name.
int work_system(std::string_view name) {
  constexpr std::array<std::string_view, 9> kNames = {"G54", "G55",   "G56",   "G57",  "G58",
                                                      "G59", "G59.1", "G59.2", "G59.3"};
  for (std::size_t k = 0; k < kNames.size(); ++k) {
    if (name == kNames[k]) return static_cast<int>(k) + 1;
  }
  return 0;
}

class MachineReader {
 public:
  explicit MachineReader(std::string source) : source_(std::move(source)) {}

  MachineDefinition read(const nlohmann::json& value) {
    if (!value.is_object())
      fail("", "expected a JSON object (docs/gcode.md, \"Coordinate systems\")");
    for (const auto& [key, _] : value.items()) {
      if (key != "units" && key != "work_offsets" && key != "g28" && key != "g30" &&
          key != "travel" && key != "tool_change" && key != "frame" && key != "comment") {
        fail(key,
             "unknown key; expected units, work_offsets, g28, g30, travel, tool_change, frame or "
             "comment");
      }
    }
    if (value.contains("units")) {
      const nlohmann::json& units = value["units"];
      if (!units.is_string() || (units != "mm" && units != "in"))
        fail("units", "expected mm or in");
      unit_ = units == "in" ? kMillimetresPerInch : 1.0;
    }
    MachineDefinition machine;
    if (value.contains("work_offsets")) {
      const nlohmann::json& offsets = value["work_offsets"];
      if (!offsets.is_object()) fail("work_offsets", "expected an object {\"G54\": [x, y, z], …}");
      for (const auto& [name, point] : offsets.items()) {
        const int system = work_system(name);
        if (system == 0) {
          fail("work_offsets", fmt::format("\"{}\": expected G54 … G59, G59.1 … G59.3", name));
        }
        machine.work_offsets[static_cast<std::size_t>(system - 1)] =
            this->point(point, "work_offsets\": \"" + name);
      }
    }
    if (value.contains("g28")) machine.g28 = point(value["g28"], "g28");
    if (value.contains("g30")) machine.g30 = point(value["g30"], "g30");
    if (value.contains("tool_change"))
      machine.tool_change = point(value["tool_change"], "tool_change");
    if (value.contains("travel")) {
      const nlohmann::json& travel = value["travel"];
      if (!travel.is_object() || !travel.contains("min") || !travel.contains("max") ||
          travel.size() != 2) {
        fail("travel", "expected {\"min\": [x, y, z], \"max\": [x, y, z]}");
      }
      Aabb box;
      box.min = point(travel["min"], "travel\": \"min");
      box.max = point(travel["max"], "travel\": \"max");
      if ((box.min.array() > box.max.array()).any()) fail("travel", "min is beyond max");
      machine.travel = box;
    }
    if (value.contains("frame")) {
      const nlohmann::json& frame = value["frame"];
      machine.frame = frame.is_string() ? work_system(frame.get<std::string>()) : 0;
      if (machine.frame == 0) fail("frame", "expected G54 … G59, G59.1 … G59.3");
    }
    return machine;
  }

 private:
  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw InputError(
        SourceLocation{key.empty() ? source_ : fmt::format("{}: \"{}\"", source_, key)}, message);
  }

  Vec3 point(const nlohmann::json& value, const std::string& key) const {
    if (!value.is_array() || value.size() != 3) fail(key, "expected [x, y, z]");
    Vec3 p;
    for (int a = 0; a < 3; ++a) {
      const nlohmann::json& v = value[static_cast<std::size_t>(a)];
      if (!v.is_number() || !std::isfinite(v.get<double>()) ||
          std::abs(v.get<double>()) > kLargestInputValue) {
        fail(key, "expected [x, y, z]: three numbers");
      }
      p[a] = v.get<double>() * unit_;
    }
    return p;
  }

  std::string source_;
  double unit_ = 1.0;
};

}  // namespace

MachineDefinition machine_from_json(const nlohmann::json& value, const std::string& source) {
  return MachineReader(source).read(value);
}

MachineDefinition read_machine_file(const std::string& path) {
  return machine_from_json(parse_json_input(read_text_file(path, "machine file"), path), path);
}

}  // namespace cwe
