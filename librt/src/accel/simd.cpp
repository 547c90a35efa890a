#include <librt/accel/simd.h>

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
            return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                   __builtin_cpu_supports("popcnt") && __builtin_cpu_supports("bmi");
        case SimdPath::Avx512:
            return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                   __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                   __builtin_cpu_supports("popcnt") && __builtin_cpu_supports("bmi");
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

SimdSelection select_simd_path(std::string_view requested) {
    SimdSelection s;
    s.requested = std::string(requested);
    const SimdPath best = supported_simd_paths().back();
    s.path = best;
    if (requested.empty() || requested == "auto") return s;
    for (const SimdPath p : {SimdPath::Scalar, SimdPath::Sse, SimdPath::Avx2, SimdPath::Avx512}) {
        if (requested != to_string(p)) continue;
        if (simd_path_supported(p)) {
            s.path = p;
        } else {
            s.note =
                "LIBRT_SIMD=" + s.requested + " is not supported here, using " + to_string(best);
        }
        return s;
    }
    s.note = "LIBRT_SIMD=" + s.requested +
             " is not one of auto, scalar, sse, avx2, avx512; using " + to_string(best);
    return s;
}

const SimdSelection& simd_selection() {
    // Read once: every TriangleBvh built in this process starts on the same path.
    static const SimdSelection selection = [] {
        const char* env = std::getenv("LIBRT_SIMD");
        return select_simd_path(env ? std::string_view(env) : std::string_view());
    }();
    return selection;
}

SimdPath default_simd_path() { return simd_selection().path; }

const std::string& simd_path_note() { return simd_selection().note; }

}  // namespace librt
