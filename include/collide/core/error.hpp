#pragma once
/// @file
/// The two tiers of error handling (STYLE.md "Errors"):
///  1. Public entry points that take user data (`make_polygon`, `make_circle`, file loaders, the
///     query tool) validate it and throw `InvalidInput`, whose message names the field and the
///     reason. Nothing is half-built when they throw.
///  2. Queries on shapes that were built by those entry points trust them; internal invariants
///     are checked by `COLLIDE_ASSERT` (enabled with COLLIDE_ENABLE_ASSERTS, the debug preset),
///     which calls a handler the user can replace.

#include <stdexcept>
#include <string>

namespace collide {

/// Thrown by public entry points for input they reject: non-finite numbers, negative radii,
/// non-convex or clockwise polygons, too few distinct vertices, malformed files. `what()` names
/// the offending field (e.g. "polygon vertex 3: not finite").
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Called when an internal assertion fails. Return true to continue (e.g. log and go on),
/// false to abort. The default prints to stderr and aborts.
using AssertHandler = bool (*)(const char* condition, const char* message, const char* file,
                               int line);

/// Replace the handler; returns the previous one. Passing nullptr restores the default.
AssertHandler set_assert_handler(AssertHandler handler) noexcept;

/// Reports a failed internal assertion to the installed handler (what `COLLIDE_ASSERT` calls):
/// `condition` as written, `message`, and the source `file` and `line`. Returns the handler's
/// answer: true to continue, false to stop (the macro then traps). Never throws.
[[nodiscard]] bool report_assert_failure(const char* condition, const char* message,
                                         const char* file, int line) noexcept;

}  // namespace collide

#if defined(COLLIDE_ENABLE_ASSERTS)
#define COLLIDE_ASSERT(cond, message)                                                     \
  do {                                                                                    \
    if (!(cond) && !::collide::report_assert_failure(#cond, message, __FILE__, __LINE__)) \
      __builtin_trap();                                                                   \
  } while (false)
#else
#define COLLIDE_ASSERT(cond, message) \
  do {                                \
    (void)sizeof(cond);               \
  } while (false)
#endif
