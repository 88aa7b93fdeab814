#pragma once
// The texts of data/materials/*.json, compiled into the library so that an installed program
// needs no data path. The definition is generated at build time by cmake/EmbedMaterials.cmake.

#include <span>
#include <string_view>

namespace cwe::detail {

struct BundledMaterial {
  std::string_view name;  // the file name without .json, lower case
  std::string_view json;  // the file's bytes
};

// Every bundled set, sorted by name.
std::span<const BundledMaterial> bundled_material_texts();

}  // namespace cwe::detail
