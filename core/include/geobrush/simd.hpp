// Vector code wider than the baseline x86-64 the build targets, by one mechanism for the whole
// program: a kernel is compiled a second time for AVX2, and the processor's features (hasAvx2,
// hasAvx2Fma) choose the copy at run time. The copy is made by GCC's and Clang's target
// attribute:
//
//   simd::fastest([&] { kernel(...); });
//
// runs the lambda inlined (with everything it calls) into a copy built for AVX2 where the
// processor has AVX2, and into a baseline copy elsewhere. Written with plain loops or GCC vector
// types, both copies do the same arithmetic in the same order; AVX2 alone brings no fused
// multiply-add, so they round alike and results never depend on the machine. `flatten` does not
// always reach through generic lambdas and the function templates they call: mark those
// [[gnu::always_inline]] where the kernel's speed depends on them, or they stay baseline code.
//
// Code written with AVX2 + FMA intrinsics that calls glibc's vector math library (libmvec) is a
// source file of its own compiled with -mavx2 -mfma, run only where simd::hasAvx2Fma() says so,
// beside a scalar twin: Clang passes a second 256-bit argument wrongly to a function whose
// declaration alone carries the target attribute, so such calls need the flags for the whole file.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define GEOBRUSH_SIMD_X86 1
#define GEOBRUSH_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define GEOBRUSH_SIMD_X86 0
#define GEOBRUSH_TARGET_AVX2
#endif

namespace geobrush::simd {

// Whether this processor runs AVX2 code (a load of what the runtime read at start-up).
inline bool hasAvx2() {
#if GEOBRUSH_SIMD_X86
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

// Whether this processor runs AVX2 code with fused multiply-adds.
inline bool hasAvx2Fma() {
#if GEOBRUSH_SIMD_X86
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

namespace detail {
template <typename Kernel>
[[gnu::flatten]] GEOBRUSH_TARGET_AVX2 decltype(auto) runAvx2(Kernel& kernel) {
  return kernel();
}
template <typename Kernel>
[[gnu::flatten]] decltype(auto) runBaseline(Kernel& kernel) {
  return kernel();
}
}  // namespace detail

// kernel() compiled for AVX2 where the processor has it, else for the baseline.
template <typename Kernel>
decltype(auto) fastest(Kernel&& kernel) {
  if (hasAvx2()) return detail::runAvx2(kernel);
  return detail::runBaseline(kernel);
}

}  // namespace geobrush::simd
