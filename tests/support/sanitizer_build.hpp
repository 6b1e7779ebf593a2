// Whether this test program runs in the sanitizer build (AddressSanitizer, scripts/test-sanitizers.sh),
// read from the compiler itself (clang's __has_feature, gcc's __SANITIZE_ADDRESS__), so no build
// option can disagree with the instrumentation.
//
// The sanitizers look for memory errors and undefined behaviour on every code path, which the
// first steps of a run reach; the Release build checks the numbers over the full horizons. A test
// whose run takes minutes under the sanitizers (20 to 40 times its Release time) may therefore
// run a shorter horizon or fewer cases there, with every code path and every bound it asserts
// unchanged, and its Release run exactly as before (docs/ci.md, "Third pass"):
//   const double t_end = test::kSanitizerBuild ? 1.0 : 10.0;
#pragma once

namespace mbd::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizerBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif
#else
inline constexpr bool kSanitizerBuild = false;
#endif

}  // namespace mbd::test
