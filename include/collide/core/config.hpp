#pragma once
/// @file
/// Compiler hints used by the hot loops.

/// Forces inlining of a small hot function whose call overhead the compiler misjudges (the
/// GJK loop and its helpers: templates called once per query, measured with callgrind).
#if defined(__GNUC__) || defined(__clang__)
#define COLLIDE_ALWAYS_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define COLLIDE_ALWAYS_INLINE __forceinline
#else
#define COLLIDE_ALWAYS_INLINE inline
#endif

/// Keeps a rarely taken path out of the hot loop that calls it (its code and registers apart).
#if defined(__GNUC__) || defined(__clang__)
#define COLLIDE_COLD __attribute__((noinline, cold))
#elif defined(_MSC_VER)
#define COLLIDE_COLD __declspec(noinline)
#else
#define COLLIDE_COLD
#endif

/// Inlines every call in the function's body, recursively, into it alone (its callees keep
/// their own out-of-line copies for other callers): for a variant of a routine that drops part
/// of its result, so that the dropped work is dead code there without the routine being forced
/// inline everywhere (raycast_fraction).
#if defined(__GNUC__) || defined(__clang__)
#define COLLIDE_FLATTEN __attribute__((flatten))
#else
#define COLLIDE_FLATTEN
#endif
