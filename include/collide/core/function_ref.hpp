#pragma once
/// @file
/// `FunctionRef`: the callback type of every query that reports results one at a time (broad
/// phases, BVH and mesh ray casts), so a query takes any lambda without templates or
/// allocation.

#include <functional>
#include <memory>
#include <type_traits>
#include <utility>

namespace collide {

/// A non-owning reference to a callable, like C++26 std::function_ref: two pointers, no
/// allocation. Must not outlive the callable it refers to.
template <class Signature>
class FunctionRef;

template <class R, class... Args>
class FunctionRef<R(Args...)> {
 public:
  /// Refers to `f` (a lambda, function or other callable as R(Args...)) without copying it:
  /// `f` must outlive this reference (use it as a parameter, not stored). Never allocates.
  template <class F>
    requires(!std::is_same_v<std::remove_cvref_t<F>, FunctionRef> &&
             std::is_invocable_r_v<R, F&, Args...>)
  FunctionRef(F&& f) noexcept  // NOLINT(google-explicit-constructor): implicit by design
      : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_([](void* object, Args... args) -> R {
          return std::invoke(*static_cast<std::remove_reference_t<F>*>(object),
                             std::forward<Args>(args)...);
        }) {}

  /// Calls the referred callable with `args` and returns its result; what it throws propagates.
  R operator()(Args... args) const { return call_(object_, std::forward<Args>(args)...); }

 private:
  void* object_;
  R (*call_)(void*, Args...);
};

}  // namespace collide
