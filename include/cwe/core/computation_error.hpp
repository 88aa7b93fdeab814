#pragma once
// Thrown when a geometric computation fails on input it accepted (a mesh boolean that the
// geometry kernel could not carry out, or whose result is not a valid solid). what() says what
// was being computed and what the kernel said; the caller adds the move and its source line. The
// command line exits with 3: the input may be fine, the computation was not.

#include <stdexcept>

namespace cwe {

class ComputationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cwe
