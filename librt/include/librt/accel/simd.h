#pragma once

#include <librt/export.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace librt {

/// The instruction sets librt's wide-BVH kernels are compiled for. All of them are in
/// every x86-64 build (each kernel carries its own target attribute, the rest of the
/// library stays baseline x86-64); the CPU picks at run time. Other architectures get
/// Scalar only. Every path returns the same hits: the kernels run the same float
/// operations in the same order (the library is compiled with -ffp-contract=off).
enum class SimdPath : std::uint8_t {
    Scalar,  ///< portable C++, one child box and one triangle at a time
    Sse,     ///< SSE2: two 4-wide halves per node, 4 triangles per test
    Avx2,    ///< AVX2: 8 child boxes per instruction, 4 triangles per test
    Avx512,  ///< AVX-512 F+VL: as AVX2 with mask registers
};

/// "scalar", "sse", "avx2" or "avx512".
[[nodiscard]] LIBRT_API const char* to_string(SimdPath path);

/// True when the kernel for `path` is compiled in and the CPU and OS support it.
[[nodiscard]] LIBRT_API bool simd_path_supported(SimdPath path);

/// Every supported path, Scalar first, best last.
[[nodiscard]] LIBRT_API std::vector<SimdPath> supported_simd_paths();

/// The path new objects start with: the best supported one, unless the environment
/// variable LIBRT_SIMD names another supported path (scalar, sse, avx2, avx512; auto or
/// unset = best). Read once, at the first call. A refused request is not printed (the
/// library never prints): simd_path_note() says why, for the caller to show.
[[nodiscard]] LIBRT_API SimdPath default_simd_path();

/// A choice of SIMD path from a request such as LIBRT_SIMD's value, and why a request was
/// not followed.
struct SimdSelection {
    SimdPath path = SimdPath::Scalar;  ///< the path chosen
    std::string requested;             ///< the request as given ("" when there was none)
    /// Empty when the request was followed (or absent, or "auto"); otherwise one line
    /// saying what was requested, why it was refused and which path is used instead, e.g.
    /// "LIBRT_SIMD=avx512 is not supported here, using avx2".
    std::string note;
};

/// The path for `requested` (a LIBRT_SIMD value; empty or "auto" = the best supported): the
/// named path when this CPU supports it, else the best supported one with a note saying
/// why. Pure: it reads no environment.
[[nodiscard]] LIBRT_API SimdSelection select_simd_path(std::string_view requested);

/// The selection behind default_simd_path(): select_simd_path(LIBRT_SIMD), made once.
[[nodiscard]] LIBRT_API const SimdSelection& simd_selection();

/// simd_selection().note: empty, or the line an app should print (to stderr) because
/// LIBRT_SIMD asked for a path that is not used.
[[nodiscard]] LIBRT_API const std::string& simd_path_note();

}  // namespace librt
