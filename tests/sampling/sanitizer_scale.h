#pragma once

// How many samples the heavy statistical tests draw in this build. The sanitizer stages
// (asan, tsan) look for memory errors, undefined behaviour and races, which a tenth of a
// test's samples reach on every code path as surely as all of them; at their 5-20x
// slowdown the full counts cost minutes (AnisotropicGgx.SampledDirectionsFollowPdf took
// 300 s under ASan). Under a sanitizer those tests therefore draw ten times fewer samples.
// Their tolerances follow from the count (standard errors; chi-square p-values over cells
// pooled to >= 5 expected samples), so they remain valid tests, only less sensitive; the
// release stage runs them at full strength. See docs/robustness.md, "Tests and time".

#include <algorithm>
#include <cstdlib>
#include <string_view>

namespace librt::testing {

/// True when compiled with AddressSanitizer or ThreadSanitizer (GCC defines
/// __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__, clang answers __has_feature), or when
/// LIBRT_SANITIZED is defined (to try the reduced counts in a plain build).
#if defined(LIBRT_SANITIZED) || defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

/// How many times fewer samples the heavy statistical tests draw: 10 under a sanitizer,
/// else 1; 1 also when the environment sets LIBRT_FULL_STATISTICS=1 (to run them at full
/// strength under a sanitizer, as when timing them).
inline int sample_divisor() {
    static const int divisor = [] {
        const char* full = std::getenv("LIBRT_FULL_STATISTICS");
        if (full != nullptr && std::string_view(full) == "1") return 1;
        return kSanitized ? 10 : 1;
    }();
    return divisor;
}

/// The sample count of a test that draws n at full strength.
inline int scaled_samples(int n) { return std::max(1, n / sample_divisor()); }

}  // namespace librt::testing
