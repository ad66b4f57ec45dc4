#include <collide/core/error.hpp>

#include <atomic>
#include <cstdio>

namespace collide {
namespace {

bool default_handler(const char* condition, const char* message, const char* file, int line) {
  std::fprintf(stderr, "collide: assertion failed: %s (%s) at %s:%d\n", condition, message, file,
               line);
  return false;
}

std::atomic<AssertHandler> g_handler{&default_handler};

}  // namespace

AssertHandler set_assert_handler(AssertHandler handler) noexcept {
  return g_handler.exchange(handler != nullptr ? handler : &default_handler);
}

bool report_assert_failure(const char* condition, const char* message, const char* file,
                           int line) noexcept {
  return g_handler.load()(condition, message, file, line);
}

}  // namespace collide
