#pragma once
// Whether this test binary is built with AddressSanitizer (EDX_SANITIZE=address,undefined
// ./edx test). Sanitizers slow instrumented code unevenly (Eigen-heavy backend code several times
// more than OpenCV, which is not instrumented), so the few assertions about the relation of
// measured host times hold for the Release build only; they check nothing about memory.
namespace edx::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif
#else
inline constexpr bool kSanitizedBuild = false;
#endif

}  // namespace edx::testing
