#pragma once
// CWE_ASSERT(condition, message): checks an internal invariant. On (CWE_ENABLE_ASSERTS) in the
// default build, the test build and the sanitizer build; compiled out otherwise. A failure is a
// bug in cwe, never a user error, so it throws cwe::InternalError naming file and line.

#include <stdexcept>
#include <string>

namespace cwe {

class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void assertion_failed(const char* condition, const char* message, const char* file,
                                   int line);

}  // namespace cwe

#if defined(CWE_ENABLE_ASSERTS) && CWE_ENABLE_ASSERTS
#define CWE_ASSERT(condition, message)                                    \
  do {                                                                    \
    if (!(condition)) {                                                   \
      ::cwe::assertion_failed(#condition, (message), __FILE__, __LINE__); \
    }                                                                     \
  } while (false)
#else
#define CWE_ASSERT(condition, message) \
  do {                                 \
  } while (false)
#endif
