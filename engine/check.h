#pragma once
// Two kinds of failure (docs/design.md, "Failure handling"): bad input throws InputError with a message
// naming the file and the place; a broken internal invariant is a CHECK, always on, which aborts with the
// failed condition.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace candela {

// Bad input from a file, a script or the command line. Caught in main, printed as `error: ...`, and the
// process exits with kBadInputExit.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The one exit status of every bad input (command-line parse errors included); 1 is left for failures
// that are not the input's fault (out of memory, no display, an unexpected exception).
inline constexpr int kBadInputExit = 2;

[[noreturn]] inline void check_failed(const char* cond, const char* file, int line) {
  std::fprintf(stderr, "CHECK failed: %s at %s:%d\n", cond, file, line);
  std::abort();
}

}  // namespace candela

#define CHECK(cond)                                                  \
  do {                                                               \
    if (!(cond)) ::candela::check_failed(#cond, __FILE__, __LINE__); \
  } while (0)
#ifdef NDEBUG
#define DCHECK(cond) \
  do {               \
  } while (0)
#else
#define DCHECK(cond) CHECK(cond)
#endif
