#pragma once

#include <librt/export.h>

#include <cstdint>
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
/// unset = best). Read once, at the first call.
[[nodiscard]] LIBRT_API SimdPath default_simd_path();

}  // namespace librt
