#include "cwe/core/error.hpp"

#include "cwe/core/assert.hpp"

namespace cwe {
namespace {

std::string format_location(const SourceLocation& location) {
  if (location.source.empty()) return {};
  std::string out = location.source;
  if (location.line > 0) {
    out += ':' + std::to_string(location.line);
    if (location.column > 0) out += ':' + std::to_string(location.column);
  }
  return out + ": ";
}

}  // namespace

InputError::InputError(SourceLocation location, const std::string& message)
    : std::runtime_error(format_location(location) + "error: " + message),
      location_(std::move(location)),
      message_(message) {}

void assertion_failed(const char* condition, const char* message, const char* file, int line) {
  throw InternalError(std::string(file) + ':' + std::to_string(line) +
                      ": internal error: assertion `" + condition + "` failed: " + message);
}

}  // namespace cwe
