#include <librt/accel/simd.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace librt {

const char* to_string(SimdPath path) {
    switch (path) {
        case SimdPath::Scalar:
            return "scalar";
        case SimdPath::Sse:
            return "sse";
        case SimdPath::Avx2:
            return "avx2";
        case SimdPath::Avx512:
            return "avx512";
    }
    return "unknown";
}

bool simd_path_supported(SimdPath path) {
    switch (path) {
        case SimdPath::Scalar:
            return true;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
        case SimdPath::Sse:
            return true;  // SSE2 is part of x86-64
        // __builtin_cpu_supports also checks that the OS saves the wider registers.
        case SimdPath::Avx2:
            return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt") &&
                   __builtin_cpu_supports("bmi");
        case SimdPath::Avx512:
            return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                   __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt") &&
                   __builtin_cpu_supports("bmi");
#else
        default:
            return false;
#endif
    }
    return false;
}

std::vector<SimdPath> supported_simd_paths() {
    std::vector<SimdPath> paths;
    for (const SimdPath p : {SimdPath::Scalar, SimdPath::Sse, SimdPath::Avx2, SimdPath::Avx512})
        if (simd_path_supported(p)) paths.push_back(p);
    return paths;
}

SimdPath default_simd_path() {
    static const SimdPath chosen = [] {
        const SimdPath best = supported_simd_paths().back();
        const char* env = std::getenv("LIBRT_SIMD");
        if (!env || !*env || std::string_view(env) == "auto") return best;
        for (const SimdPath p :
             {SimdPath::Scalar, SimdPath::Sse, SimdPath::Avx2, SimdPath::Avx512}) {
            if (std::string_view(env) != to_string(p)) continue;
            if (simd_path_supported(p)) return p;
            std::fprintf(stderr, "librt: LIBRT_SIMD=%s is not supported here, using %s\n", env,
                         to_string(best));
            return best;
        }
        std::fprintf(
            stderr,
            "librt: LIBRT_SIMD=%s is not one of auto, scalar, sse, avx2, avx512; using %s\n", env,
            to_string(best));
        return best;
    }();
    return chosen;
}

}  // namespace librt
