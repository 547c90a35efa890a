// AVX2 wide-BVH kernels: the eight child boxes of a node in one 8-lane test, four triangles per
// test. Only this file's kernels are compiled for the instruction set (a target pragma around them,
// not a -m flag on the file), so nothing here can leak into baseline code; they run only when
// simd_path_supported() says the CPU has it.

#include "wide_kernels.h"

#if defined(LIBRT_HAVE_X86_KERNELS)
#include <librt/accel/bvh_traversal.h>
#include <librt/geometry/triangle.h>

#include <immintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,popcnt,bmi"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,popcnt,bmi")
#endif

namespace librt::detail::avx2 {
namespace {

#include "block4_sse.inl"

#define LIBRT_WIDE_HIT_MASK(enter, exit) \
    static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OQ)))
#include "wide_avx8.inl"
#undef LIBRT_WIDE_HIT_MASK

}  // namespace librt::detail::avx2

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
