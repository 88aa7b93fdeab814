#pragma once
// Thrown when a geometric computation fails on input it accepted (a mesh boolean that the
// geometry kernel could not carry out, or whose result is not a valid solid). what() says what
// was being computed and what the kernel said; the main loop adds the move's file and line. The
// command line exits with 3: the input may be fine, the computation was not.

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>

namespace cwe {

class ComputationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // The same error, naming which of several inputs (a sweep of a batch) it came from.
  ComputationError(std::size_t item, const std::string& message)
      : std::runtime_error(message), item_(item) {}
  const std::optional<std::size_t>& item() const { return item_; }

 private:
  std::optional<std::size_t> item_;
};

}  // namespace cwe
