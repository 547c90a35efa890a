// AVX2 wide-BVH kernel: the eight child boxes of a node in one 8-lane fused (FMA) test
// (slab8_avx.h), four triangles per test (block4_sse.h, VEX-encoded here). Only this file's kernel
// is compiled for the instruction set (a target pragma around it, not a -m flag on the file, so
// nothing leaks into baseline code); it runs only when simd_path_supported() says the CPU has it.
// The entry points are flatten: the baseline traversal template and the block test are inlined into
// them, so all of it is compiled for AVX2. Why this file and wide_avx512.cpp still repeat their
// pragmas and entry points: a target applies to the functions defined under it, so each instruction
// set's entry points must be defined in its own file under its own pragma (a template entry point
// in a shared header would be compiled for baseline x86-64, and flatten could not inline AVX code
// into it); sharing the pragma text itself would take a macro or a textual include.

#include "wide_kernels.h"

#if defined(LIBRT_HAVE_X86_KERNELS)
#include "block4_sse.h"
#include "slab8_avx.h"
#include "wide_stream.h"
#include "wide_traversal.h"

#include <immintrin.h>

#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma,popcnt,bmi"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma,popcnt,bmi")
#endif

namespace librt::detail {
namespace {

/// The WideKernel policy of the AVX2 path.
struct Avx2Kernel : Block4Triangles, Slab8Nodes {
    /// slab_test8, its hit lanes gathered by movemask.
    static std::uint32_t intersect_node(const WideBvhNode& node, const NodeRay& r, float t_min,
                                        float t_max, float* t_enter) {
        __m256 enter, exit;
        slab_test8(node, r, t_min, t_max, t_enter, enter, exit);
        return static_cast<std::uint32_t>(
            _mm256_movemask_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OQ)));
    }
};
static_assert(WideKernel<Avx2Kernel>);

// A ray from beyond slab_test8's range (slab8_in_range) takes the SSE kernel: the same hits.
[[gnu::flatten]] PrimitiveHit avx2_intersect(const WideBvh& bvh, const Ray& ray) {
    if (!slab8_in_range(ray)) [[unlikely]]
        return sse_wide_kernels().intersect(bvh, ray);
    return intersect_wide<Avx2Kernel>(bvh, ray);
}
[[gnu::flatten]] bool avx2_occluded(const WideBvh& bvh, const Ray& ray) {
    if (!slab8_in_range(ray)) [[unlikely]]
        return sse_wide_kernels().occluded(bvh, ray);
    return occluded_wide<Avx2Kernel>(bvh, ray);
}
[[gnu::flatten]] PrimitiveHit avx2_intersect_normal(const WideBvh& bvh, const Ray& ray,
                                                    glm::vec3& normal) {
    if (!slab8_in_range(ray)) [[unlikely]]
        return sse_wide_kernels().intersect_normal(bvh, ray, normal);
    return intersect_normal_wide<Avx2Kernel>(bvh, ray, normal);
}

// The stream: rays beyond slab_test8's range go one by one through the SSE kernel.
[[gnu::flatten]] void avx2_intersect_stream(const WideBvh& bvh, const Ray* rays, PrimitiveHit* hits,
                                            std::size_t count) {
    traverse_wide_stream<Avx2Kernel, false>(
        bvh, rays, hits, count, [](const Ray& ray) { return slab8_in_range(ray); },
        [&](const Ray& ray) { return sse_wide_kernels().intersect(bvh, ray); });
}
[[gnu::flatten]] void avx2_occluded_stream(const WideBvh& bvh, const Ray* rays,
                                           std::uint8_t* blocked, std::size_t count) {
    traverse_wide_stream<Avx2Kernel, true>(
        bvh, rays, blocked, count, [](const Ray& ray) { return slab8_in_range(ray); },
        [&](const Ray& ray) {
            return static_cast<std::uint8_t>(sse_wide_kernels().occluded(bvh, ray) ? 1 : 0);
        });
}

}  // namespace

WideKernels avx2_wide_kernels() {
    return {&avx2_intersect, &avx2_occluded, &avx2_intersect_normal, &avx2_intersect_stream,
            &avx2_occluded_stream};
}

}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
