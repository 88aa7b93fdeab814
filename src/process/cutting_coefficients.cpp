#include "cwe/process/cutting_coefficients.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string_view>
#include <system_error>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bundled_materials.hpp"
#include "cwe/core/error.hpp"
#include "cwe/core/json_input.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe {
namespace {

// Label of errors about a material name given on its own (not in a file).
constexpr const char* kNameSource = kCoefficientNameSource;

constexpr const char* kExpectedKeys =
    "a set has the six keys Ktc, Krc, Kac (shear terms, N/mm²) and Kte, Kre, Kae "
    "(edge terms, N/mm)";

struct Key {
  const char* name;
  double CuttingCoefficients::*field;
  const char* unit;
};

constexpr Key kKeys[] = {
    {"Ktc", &CuttingCoefficients::ktc, "N/mm²"}, {"Krc", &CuttingCoefficients::krc, "N/mm²"},
    {"Kac", &CuttingCoefficients::kac, "N/mm²"}, {"Kte", &CuttingCoefficients::kte, "N/mm"},
    {"Kre", &CuttingCoefficients::kre, "N/mm"},  {"Kae", &CuttingCoefficients::kae, "N/mm"},
};

std::string lower_case(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// A key that differs from `wanted` only in case, to point out a misspelt key; empty if none.
std::string same_key_other_case(const nlohmann::json& j, const std::string& wanted) {
  for (const auto& [key, unused] : j.items()) {
    if (lower_case(key) == lower_case(wanted)) return key;
  }
  return {};
}

std::string bundled_names() {
  std::string out;
  for (const detail::BundledMaterial& m : detail::bundled_material_texts()) {
    if (!out.empty()) out += ", ";
    out += m.name;
  }
  return out.empty() ? std::string("none") : out;
}

const detail::BundledMaterial* find_bundled(const std::string& name) {
  const std::string wanted = lower_case(name);
  for (const detail::BundledMaterial& m : detail::bundled_material_texts()) {
    if (m.name == wanted) return &m;
  }
  return nullptr;
}

CuttingCoefficients from_bundled(const detail::BundledMaterial& m) {
  return parse_cutting_coefficients(m.json, fmt::format("{}.json (bundled)", m.name));
}

}  // namespace

CuttingCoefficients parse_cutting_coefficients(std::string_view json_text,
                                               const std::string& source) {
  const SourceLocation where{source};
  const nlohmann::json j = parse_json_input(json_text, source);
  if (!j.is_object()) {
    throw InputError(where, fmt::format("expected a JSON object {{\"Ktc\": …, \"Krc\": …, …}}; {}",
                                        kExpectedKeys));
  }

  CuttingCoefficients set;
  for (const Key& key : kKeys) {
    if (!j.contains(key.name)) {
      const std::string other = same_key_other_case(j, key.name);
      if (!other.empty()) {
        throw InputError(where,
                         fmt::format("missing \"{}\" (found \"{}\"; keys are case-sensitive); {}",
                                     key.name, other, kExpectedKeys));
      }
      throw InputError(where, fmt::format("missing \"{}\"; {}", key.name, kExpectedKeys));
    }
    const nlohmann::json& value = j[key.name];
    if (!value.is_number()) {
      throw InputError(where, fmt::format("\"{}\": expected a number in {}, found {}", key.name,
                                          key.unit, value.dump()));
    }
    const double number = value.get<double>();
    // The parser already refuses overflow; the bound keeps every product the force model forms
    // finite (text_file.hpp).
    if (!std::isfinite(number) || std::abs(number) > kLargestInputValue) {
      throw InputError(where, fmt::format("\"{}\": {} {} is out of range (magnitude above {:g})",
                                          key.name, value.dump(), key.unit, kLargestInputValue));
    }
    set.*key.field = number;
  }
  // Negative terms occur in published sets (K_ac in particular, whose sign depends on the axial
  // direction a source chose), but a set without any shear term predicts no chip-load force at
  // all, which is never what a user meant.
  if (set.ktc == 0.0 && set.krc == 0.0 && set.kac == 0.0) {
    throw InputError(where,
                     "the shear terms Ktc, Krc and Kac are all zero; at least one must be non-zero "
                     "(N/mm²)");
  }

  const auto text_of = [&](const char* key, std::string& field) {
    if (!j.contains(key)) return;
    if (!j[key].is_string()) {
      throw InputError(where,
                       fmt::format("\"{}\": expected a string, found {}", key, j[key].dump()));
    }
    field = j[key].get<std::string>();
  };
  set.name = source;
  text_of("name", set.name);
  text_of("source", set.source);
  return set;
}

std::vector<std::string> bundled_materials() {
  std::vector<std::string> names;
  for (const detail::BundledMaterial& m : detail::bundled_material_texts()) {
    names.emplace_back(m.name);
  }
  return names;
}

CuttingCoefficients bundled_coefficients(const std::string& name) {
  const detail::BundledMaterial* m = find_bundled(name);
  if (m == nullptr) {
    throw InputError(SourceLocation{kNameSource},
                     fmt::format("unknown material '{}' (bundled: {})", name, bundled_names()));
  }
  return from_bundled(*m);
}

CuttingCoefficients load_cutting_coefficients(const std::string& name_or_path) {
  const std::filesystem::path path(name_or_path);
  const bool looks_like_file = lower_case(path.extension().string()) == ".json" ||
                               name_or_path.find('/') != std::string::npos;
  if (!looks_like_file) {
    if (const detail::BundledMaterial* m = find_bundled(name_or_path)) return from_bundled(*m);
  }
  std::error_code error;
  if (looks_like_file || std::filesystem::is_regular_file(path, error)) {
    return parse_cutting_coefficients(read_text_file(name_or_path, "cutting-coefficient file"),
                                      name_or_path);
  }
  throw InputError(SourceLocation{kNameSource},
                   fmt::format("'{}' is neither a bundled material ({}) nor a file", name_or_path,
                               bundled_names()));
}

}  // namespace cwe
