// Loading the OpenCASCADE module (cwe/io/occt.hpp) and the functions of cwe/io/step.hpp that
// call into it. Nothing here includes OpenCASCADE.

#include "cwe/io/occt.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cwe/core/computation_error.hpp"

namespace cwe {
namespace {

constexpr const char* kModuleFile = "libcwe-occt.so";

// The places to look, in order (the header says why each).
std::vector<std::filesystem::path> module_paths() {
  std::vector<std::filesystem::path> paths;
  if (const char* given = std::getenv("CWE_OCCT_MODULE"); given != nullptr && *given != '\0') {
    paths.emplace_back(given);
  }
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path folder = program.parent_path();
    paths.push_back(folder / kModuleFile);
    paths.push_back((folder / CWE_OCCT_FROM_BIN / kModuleFile).lexically_normal());
  }
  // This code in a shared object of its own (the Python package's _cwe module): from its folder.
  Dl_info self{};
  if (*CWE_OCCT_FROM_PYTHON != '\0' &&
      ::dladdr(reinterpret_cast<const void*>(&module_paths), &self) != 0 &&
      self.dli_fname != nullptr) {
    const std::filesystem::path object = std::filesystem::absolute(self.dli_fname, ec);
    if (!ec && object != program) {
      paths.push_back(
          (object.parent_path() / CWE_OCCT_FROM_PYTHON / kModuleFile).lexically_normal());
    }
  }
  paths.push_back(std::filesystem::path(CWE_INSTALL_FULL_LIBDIR) / "cwe" / kModuleFile);
  paths.push_back(std::filesystem::path(CWE_BUILD_DIR) / kModuleFile);
  return paths;
}

}  // namespace

const OcctModule& load_occt_module(const std::vector<std::filesystem::path>& paths) {
  using Entry = const OcctModule* (*)(const char*);
  std::vector<std::string> tried;
  for (const std::filesystem::path& path : paths) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried.push_back(fmt::format("{} (no such file)", path.string()));
      continue;
    }
    // Never closed: the stocks and models it made hold its code until the process ends.
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      tried.push_back(fmt::format("{} ({})", path.string(), ::dlerror()));
      continue;
    }
    const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "cwe_occt_module"));
    const OcctModule* module = entry != nullptr ? entry(CWE_OCCT_MODULE_KEY) : nullptr;
    if (module == nullptr) {
      tried.push_back(fmt::format("{} (not the module of this build of cwe, {})", path.string(),
                                  CWE_OCCT_MODULE_KEY));
      ::dlclose(handle);
      continue;
    }
    return *module;
  }
  std::string list;
  for (const std::string& place : tried) list += "\n  " + place;
  throw ComputationError(fmt::format(
      "STEP files and the B-rep workpiece need cwe's OpenCASCADE module, {}, which could not "
      "be loaded; looked in:{}\nSet CWE_OCCT_MODULE to its path.",
      kModuleFile, list));
}

const OcctModule& occt() {
  // A failed load throws out of the initialisation, so the next call tries again.
  static const OcctModule& module = load_occt_module(module_paths());
  return module;
}

std::unique_ptr<Workpiece> brep_workpiece(BrepStock& stock, double spacing) {
  return occt().workpiece(stock, spacing);
}

bool is_step_path(std::string_view path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  std::string lower(ext.size(), '\0');
  std::transform(ext.begin(), ext.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower == ".step" || lower == ".stp";
}

StepModel StepModel::read(const std::string& path) { return occt().read_step(path); }
Aabb StepModel::bounds() const { return occt().bounds(*this); }
TriangleMesh StepModel::tessellate(double deviation) const {
  return occt().tessellate(*this, deviation);
}
StepModel mesh_solid_model(const TriangleMesh& mesh, const std::string& source) {
  return occt().mesh_solid_model(mesh, source);
}
BrepStock brep_stock(const StepModel& model) { return occt().brep_stock(model); }
BrepStock brep_stock(const Aabb& box) { return occt().brep_stock(box); }
std::string step_bytes(const BrepStock& stock) { return occt().step_bytes(stock); }
TriangleMesh tessellate(const BrepStock& stock, double deviation) {
  return occt().tessellate(stock, deviation);
}

}  // namespace cwe
