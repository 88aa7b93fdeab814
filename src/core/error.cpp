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

InputErrors::InputErrors(std::vector<InputError> errors, std::size_t more)
    : InputError(errors.at(0).location(), errors.at(0).message()),
      errors_(std::move(errors)),
      more_(more) {
  for (std::size_t i = 0; i < errors_.size(); ++i) {
    text_ += (i > 0 ? "\n" : "") + std::string(errors_[i].what());
  }
  if (more_ > 0) {
    text_ += "\n… and " + std::to_string(more_) + " more error" + (more_ == 1 ? "" : "s");
  }
}

void assertion_failed(const char* condition, const char* message, const char* file, int line) {
  throw InternalError(std::string(file) + ':' + std::to_string(line) +
                      ": internal error: assertion `" + condition + "` failed: " + message);
}

}  // namespace cwe
