#pragma once

// Experiment (reverted): closest-hit ordering of a wide node's hit children in registers,
// shared by the AVX2 and AVX-512 kernels.

#include "slab8_avx.h"
#include "wide_traversal.h"

#include <immintrin.h>

#include <bit>
#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma,popcnt,bmi"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma,popcnt,bmi")
#endif

namespace librt::detail {

/// Experiment (closest hit): a node visit with its hit children ordered in registers,
/// the same order as traverse_wide's (two: the farther deferred, the lower slot nearer on
/// a tie; three: a stable bubble network, i.e. the insertion sort's order), without the
/// t_enter store and reload; four or more as traverse_wide. False when no child is hit.
inline bool order_children8(const WideBvhNode& node, __m256 enter, std::uint32_t mask,
                            const WideBvhNode* nodes, const TriangleBlock* blocks,
                            WideStackEntry* stack, std::uint32_t& sp,
                            std::uint32_t& current) {
    if (mask == 0) return false;
    const auto i0 = static_cast<std::uint32_t>(std::countr_zero(mask));
    std::uint32_t rest = mask & (mask - 1);
    if (rest == 0) {
        current = node.child[i0];
        return true;
    }
    const auto i1 = static_cast<std::uint32_t>(std::countr_zero(rest));
    rest &= rest - 1;
    const auto i2p = static_cast<std::uint32_t>(std::countr_zero(rest | 0x100u)) & 7u;
    // The first three hit lanes' distances in lanes 0-2, in slot order (one vpermps).
    const __m256 packed = _mm256_permutevar8x32_ps(
        enter, _mm256_castsi128_si256(_mm_setr_epi32(static_cast<int>(i0),
                                                     static_cast<int>(i1),
                                                     static_cast<int>(i2p), 0)));
    const __m128 lo = _mm256_castps256_ps128(packed);
    const float d0 = _mm_cvtss_f32(lo);
    const float d1 = _mm_cvtss_f32(_mm_movehdup_ps(lo));
    if (rest == 0) {
        const bool swap = d1 < d0;
        const std::uint32_t c0 = node.child[i0], c1 = node.child[i1];
        const std::uint32_t far = swap ? c0 : c1;
        prefetch_child(nodes, blocks, far);
        stack[sp++] = {far, swap ? d0 : d1};
        current = swap ? c1 : c0;
        return true;
    }
    const auto i2 = static_cast<std::uint32_t>(std::countr_zero(rest));
    rest &= rest - 1;
    if (rest == 0) {
        std::uint32_t c0 = node.child[i0], c1 = node.child[i1], c2 = node.child[i2];
        prefetch_child(nodes, blocks, c0);
        prefetch_child(nodes, blocks, c1);
        prefetch_child(nodes, blocks, c2);
        float e0 = d0, e1 = d1, e2 = _mm_cvtss_f32(_mm_unpackhi_ps(lo, lo));
        // Bubble network, farthest first (stable: a strict compare swaps neighbours only).
        const auto cas = [](float& da, std::uint32_t& ca, float& db, std::uint32_t& cb) {
            const bool s = da < db;
            const float ta = s ? db : da, tb = s ? da : db;
            const std::uint32_t ua = s ? cb : ca, ub = s ? ca : cb;
            da = ta;
            db = tb;
            ca = ua;
            cb = ub;
        };
        cas(e0, c0, e1, c1);
        cas(e1, c1, e2, c2);
        cas(e0, c0, e1, c1);
        stack[sp] = {c0, e0};
        stack[sp + 1] = {c1, e1};
        sp += 2;
        current = c2;
        return true;
    }
    // Four or more: as traverse_wide.
    alignas(32) float t_enter[kWideBvhWidth];
    _mm256_store_ps(t_enter, enter);
    const std::uint32_t base = sp;
    prefetch_child(nodes, blocks, node.child[i0]);
    prefetch_child(nodes, blocks, node.child[i1]);
    prefetch_child(nodes, blocks, node.child[i2]);
    stack[sp++] = {node.child[i0], t_enter[i0]};
    stack[sp++] = {node.child[i1], t_enter[i1]};
    stack[sp++] = {node.child[i2], t_enter[i2]};
    do {
        const auto i = static_cast<std::uint32_t>(std::countr_zero(rest));
        rest &= rest - 1;
        prefetch_child(nodes, blocks, node.child[i]);
        stack[sp++] = {node.child[i], t_enter[i]};
    } while (rest != 0);
    for (std::uint32_t k = base + 1; k < sp; ++k) {
        const WideStackEntry e = stack[k];
        std::uint32_t j = k;
        for (; j > base && stack[j - 1].t_enter < e.t_enter; --j) stack[j] = stack[j - 1];
        stack[j] = e;
    }
    current = stack[--sp].ref;
    return true;
}

}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
