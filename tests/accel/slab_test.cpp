// The one slab test (geometry/bbox.h's slab_test) in its two forms a caller sees: one box at
// a time (intersect(BBox, SlabRay, ...), the binary BVH's) and four boxes at a time
// (accel/slab4.h, the SSE kernel's and the scene top level's). They must agree bit for bit;
// an empty box is never entered; and the widened exit keeps every box the exact ray
// touches, which the unwidened test does not. The AVX kernels' fused form (accel/
// slab8_avx.h) is checked against the same test in double: it too keeps every such box.

#include "accel/slab4.h"
#include "accel/slab8_avx.h"
#include "accel/wide_bvh.h"

#include <librt/accel/simd.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace librt;

namespace {

/// Four boxes as slab4.h's plane rows: rows[p][i] is plane p (lo.x, hi.x, ..., hi.z) of box i.
struct Rows {
    float rows[6][4];
    void set(std::uint32_t i, const BBox& b) {
        for (int a = 0; a < 3; ++a) {
            rows[2 * a][i] = b.lo[a];
            rows[2 * a + 1][i] = b.hi[a];
        }
    }
};

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// A random ray towards the boxes: sometimes with zero (or -0) direction components, sometimes a
/// finite t_max.
Ray random_ray(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-4.0f, 4.0f);
    std::uniform_int_distribution<int> pick(0, 7);
    Ray r;
    r.origin = {u(rng), u(rng), u(rng)};
    r.direction = glm::vec3(u(rng), u(rng), u(rng)) * 0.75f - r.origin;  // into the boxes' cube
    for (int a = 0; a < 3; ++a) {
        const int k = pick(rng);
        if (k == 0) r.direction[a] = 0.0f;
        if (k == 1) r.direction[a] = -0.0f;
    }
    if (r.direction == glm::vec3(0.0f)) r.direction.z = 1.0f;
    if (pick(rng) < 2) r.t_max = std::abs(u(rng));
    return r;
}

BBox random_box(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    std::uniform_int_distribution<int> pick(0, 9);
    const int k = pick(rng);
    if (k == 0) return BBox{};  // empty
    const glm::vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    BBox box(glm::min(a, b), glm::max(a, b));
    if (k == 1) box.hi.y = box.lo.y;  // flat
    return box;
}

}  // namespace

TEST(SlabTest, FourBoxFormAgreesWithTheOneBoxForm) {
    std::mt19937 rng(11);
    std::size_t hits = 0, tests = 0;
    for (int n = 0; n < 20000; ++n) {
        const Ray ray = random_ray(rng);
        BBox boxes[4];
        Rows rows;
        for (std::uint32_t i = 0; i < 4; ++i) rows.set(i, boxes[i] = random_box(rng));
        float enter[4];
        const std::uint32_t mask = detail::slab_test4(
            &rows.rows[0][0], 4, detail::prepare_slab4(ray), ray.t_min, ray.t_max, enter);
        const SlabRay one(ray);
        for (std::uint32_t i = 0; i < 4; ++i) {
            const SlabInterval s = intersect(boxes[i], one, ray.t_min, ray.t_max);
            ASSERT_EQ(s.hit(), ((mask >> i) & 1u) != 0) << "ray " << n << " box " << i;
            if (s.hit()) {
                ASSERT_TRUE(same_bits(s.t_enter, enter[i])) << s.t_enter << " vs " << enter[i];
            }
            if (boxes[i].empty()) {
                ASSERT_FALSE(s.hit()) << "an empty box was entered";
            }
            hits += s.hit();
            ++tests;
        }
    }
    // Both outcomes are well represented, so agreement means something.
    EXPECT_GT(hits, tests / 10);
    EXPECT_LT(hits, tests * 9 / 10);
}

TEST(SlabTest, WidenedExitKeepsEveryBoxTheExactRayTouches) {
    // Rays from far away aimed at points on a small box's edges: entry and exit then nearly
    // coincide, and float rounding can put the computed entry past the computed exit. The
    // reference is the same test in double (the plane differences are exact there, and the
    // remaining error is 1e-16 relative): every box it enters with some margin, the
    // widened float test must enter too.
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_int_distribution<int> pick(0, 1);
    const BBox box({0.1f, 0.2f, 0.3f}, {0.4f, 0.7f, 0.5f});
    std::size_t reference_hits = 0, robust_misses = 0, plain_misses = 0;
    for (int n = 0; n < 200000; ++n) {
        // A point on an edge parallel to axis e: the other two coordinates on box planes.
        const int e = n % 3;
        glm::vec3 target;
        for (int a = 0; a < 3; ++a) {
            const float t = 0.5f * (u(rng) + 1.0f);
            target[a] = a == e ? box.lo[a] + t * (box.hi[a] - box.lo[a])
                               : (pick(rng) ? box.hi[a] : box.lo[a]);
        }
        Ray ray;
        ray.origin = glm::vec3(u(rng), u(rng), u(rng)) * 3000.0f;
        ray.direction = target - ray.origin;
        // Reference, in double.
        double enter = 0.0, exit = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            const double inv = 1.0 / double(ray.direction[a]);
            double t0 = (double(box.lo[a]) - double(ray.origin[a])) * inv;
            double t1 = (double(box.hi[a]) - double(ray.origin[a])) * inv;
            if (t0 > t1) std::swap(t0, t1);
            enter = std::max(enter, t0);
            exit = std::min(exit, t1);
        }
        if (!(enter <= exit - 1e-12 * exit)) continue;  // a miss, or too close to call
        ++reference_hits;
        const SlabRay r(ray);
        robust_misses += !intersect(box, r, ray.t_min, ray.t_max).hit();
        float near[3], far[3];
        for (int a = 0; a < 3; ++a) {
            near[a] = r.enters_hi[a] ? box.hi[a] : box.lo[a];
            far[a] = r.enters_hi[a] ? box.lo[a] : box.hi[a];
        }
        float t_enter, t_exit;
        slab_test<false>(near, far, r.origin, r.inv_dir, ray.t_min, ray.t_max, t_enter, t_exit);
        plain_misses += !(t_enter <= t_exit);
    }
    ASSERT_GT(reference_hits, 1000u);
    EXPECT_EQ(robust_misses, 0u) << "of " << reference_hits << " boxes the exact ray enters";
    // The rays do probe the rounding: without the widening some of these boxes are lost.
    EXPECT_GT(plain_misses, 0u);
}

namespace {

/// slab_test8 (the AVX kernels' fused node test) on eight boxes.
[[gnu::target("avx2,fma")]] std::uint32_t fused_test8(const detail::WideBvhNode& node,
                                                      const Ray& ray) {
    const detail::SlabRay8 r = detail::prepare_slab8(ray);
    alignas(32) float t_enter[8];
    __m256 enter, exit;
    detail::slab_test8(node, r, ray.t_min, ray.t_max, t_enter, enter, exit);
    return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OQ)));
}

/// bbox.h's slab test of one box in double, with safe_inverse's meaning of a tiny or zero
/// direction component (+-1e-30 with its sign): the plane differences are exact or within
/// 1e-16 relative, so this is the exact test up to boxes within ~1e-16 of grazing. Returns
/// the entry and exit distances; the box is entered when enter <= exit.
std::pair<double, double> reference_slab(const BBox& box, const Ray& ray) {
    double enter = ray.t_min, exit = ray.t_max;
    for (int a = 0; a < 3; ++a) {
        const float d = ray.direction[a];
        const double safe = std::fabs(d) < 1e-30f ? std::copysign(1e-30, double(d)) : double(d);
        double t0 = (double(box.lo[a]) - double(ray.origin[a])) / safe;
        double t1 = (double(box.hi[a]) - double(ray.origin[a])) / safe;
        if (safe < 0.0) std::swap(t0, t1);
        enter = std::max(enter, t0);
        exit = std::min(exit, t1);
    }
    return {enter, exit};
}

/// The fused form without its safeguards: fl(p x inv - fl(o x inv)), no exit widening.
bool plain_fused_hit(const BBox& box, const Ray& ray) {
    const glm::vec3 inv = safe_inverse(ray.direction);
    float enter = ray.t_min, exit = ray.t_max;
    for (int a = 0; a < 3; ++a) {
        const float oi = ray.origin[a] * inv[a];
        float t0 = std::fma(box.lo[a], inv[a], -oi), t1 = std::fma(box.hi[a], inv[a], -oi);
        if (std::signbit(inv[a])) std::swap(t0, t1);
        enter = std::max(enter, t0);
        exit = std::min(exit, t1);
    }
    return enter <= exit;
}

}  // namespace

TEST(SlabTest, FusedEightBoxFormKeepsEveryBoxTheExactRayTouches) {
    if (!simd_path_supported(SimdPath::Avx2)) {
        GTEST_SKIP() << "slab_test8 needs AVX2 and FMA, which this CPU lacks";
    }
    // Rays aimed at points on boxes' faces, edges and corners (grazing, where entry and
    // exit coincide), or near them, from origins near and far (up to 2^25, the kernels'
    // range is 2^26), with direction components of every scale: zero, +-0, below
    // safe_inverse's 1e-30, tiny, huge. Eight boxes per test, as a node holds them.
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_int_distribution<int> pick(0, 7);
    const float origin_scales[] = {1.0f, 10.0f, 3000.0f, 1e5f, 0x1p25f};
    const float direction_scales[] = {0.0f, 1e-35f, 1e-25f, 1e-6f, 1.0f, 1e12f};
    std::size_t reference_hits = 0, grazing = 0, misses = 0, plain_misses = 0, tests = 0;
    for (int n = 0; n < 40000; ++n) {
        // The boxes: random, at a random offset and scale so some sit far from the origin.
        const float offset = u(rng) * origin_scales[pick(rng) % 5];
        const float scale = std::ldexp(1.0f, pick(rng) * 3 - 10);
        detail::WideBvhNode node{};
        BBox boxes[8];
        for (std::uint32_t i = 0; i < 8; ++i) {
            const glm::vec3 a = glm::vec3(u(rng), u(rng), u(rng)) * scale + offset;
            const glm::vec3 b = glm::vec3(u(rng), u(rng), u(rng)) * scale + offset;
            boxes[i] = BBox(glm::min(a, b), glm::max(a, b));
            if (pick(rng) == 0) boxes[i].hi.x = boxes[i].lo.x;  // flat
            if (i == 7 && pick(rng) < 2) boxes[i] = BBox{};     // an empty slot
            for (int k = 0; k < 3; ++k) {
                node.bounds[2 * k][i] = boxes[i].lo[k];
                node.bounds[2 * k + 1][i] = boxes[i].hi[k];
            }
        }
        // A target on box 0: a corner, or a point on an edge or a face.
        const BBox& box = boxes[0];
        glm::vec3 target;
        const int kind = pick(rng) % 3;  // how many coordinates lie on a plane: 3, 2 or 1
        for (int a = 0; a < 3; ++a) {
            const bool on_plane = a < 3 - kind;
            const float t = 0.5f * (u(rng) + 1.0f);
            target[a] = on_plane ? (pick(rng) < 4 ? box.hi[a] : box.lo[a])
                                 : box.lo[a] + t * (box.hi[a] - box.lo[a]);
        }
        Ray ray;
        ray.origin = glm::vec3(u(rng), u(rng), u(rng)) * origin_scales[pick(rng) % 5];
        ray.direction = target - ray.origin;
        if (pick(rng) < 3) {  // direction components of other scales, some axis-parallel
            const int a = pick(rng) % 3;
            const float s = direction_scales[static_cast<std::size_t>(pick(rng)) % 6];
            ray.direction[a] = pick(rng) < 4 ? s : -s;
            if (pick(rng) == 0) ray.direction[(a + 1) % 3] *= 1e10f;
        }
        if (ray.direction == glm::vec3(0.0f)) ray.direction.z = 1.0f;
        if (pick(rng) == 0) ray.t_max = std::fabs(u(rng)) * 2.0f;
        if (!detail::slab8_in_range(ray)) continue;
        const std::uint32_t mask = fused_test8(node, ray);
        for (std::uint32_t i = 0; i < 8; ++i) {
            ++tests;
            const auto [enter, exit] = reference_slab(boxes[i], ray);
            if (!(enter <= exit)) continue;
            ++reference_hits;
            grazing += enter >= exit * (1.0 - 1e-6);
            if (((mask >> i) & 1u) == 0) {
                ++misses;
                ADD_FAILURE() << "ray " << n << " box " << i << " entered at " << enter
                              << ", left at " << exit << " in double, missed";
            }
            plain_misses += !plain_fused_hit(boxes[i], ray);
            if (boxes[i].empty()) ADD_FAILURE() << "an empty box was entered in double";
        }
        if (boxes[7].empty()) ASSERT_EQ((mask >> 7) & 1u, 0u) << "an empty box was entered";
    }
    ASSERT_GT(reference_hits, tests / 20);
    EXPECT_GT(grazing, 1000u) << "too few grazing boxes to probe the rounding";
    EXPECT_EQ(misses, 0u) << "of " << reference_hits << " boxes the exact ray enters";
    // The rays do probe the rounding: the fused form without its safeguards loses some.
    EXPECT_GT(plain_misses, 0u);
}
