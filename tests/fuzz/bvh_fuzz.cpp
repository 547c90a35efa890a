// libFuzzer target: raw float triangles (bit patterns: denormals, huge, NaN, infinities,
// equal corners) straight into every BVH builder and traversal, checked against the
// linear scan. Issue 10's defect 1 (the SAH builder's bins indexed with INT_MIN for a
// denormal centroid extent) is the kind of bug this finds: the OBJ fuzzer reaches the
// builders only through decimal text, rarely with such bit patterns.
//
// Input: byte 0 picks the SAH settings (bin count, leaf size), then 36 bytes per triangle
// (nine little-endian floats, taken bit for bit), at most 64 triangles; what is left of a
// triangle's 36 bytes is ignored.
// Run: ./build/fuzz/tests/fuzz/bvh_fuzz -max_total_time=60 tests/fuzz/corpus/bvh
//
// Invariants (any breach traps):
// - the builders either throw librt::Error (a non-finite centre, a NaN box) or return a
//   tree whose leaves hold every primitive exactly once, of depth <= kMaxBvhDepth;
// - for finite triangles, every walk runs to the end; for triangles within +-2^38 (so the
//   rays' origins, at most the scene's diagonal away, stay in the representable range
//   +-kMaxMeshCoordinate of docs/robustness.md) and oblique rays, TriangleBvh (median and
//   SAH) and a walk of each binary tree find a hit exactly when the linear scan does, never
//   nearer than the scan's, and any-hit agrees;
// - TriangleBvh's ray streams (all the rays above, in any range, in one span) give each
//   ray's single-ray answer bit for bit.

#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {

using namespace librt;

float float_at(const std::uint8_t* p) {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits |= std::uint32_t{p[i]} << (8 * i);
    float f = 0.0f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check_tree(const Bvh& bvh, std::size_t n) {
    if (bvh.prim_indices.size() != n || bvh.depth > kMaxBvhDepth) __builtin_trap();
    std::vector<std::uint8_t> seen(n, 0);
    for (const BvhNode& node : bvh.nodes) {
        if (!node.is_leaf()) continue;
        for (std::uint32_t s = node.index; s < node.index + node.prim_count; ++s) {
            if (s >= n) __builtin_trap();
            const std::uint32_t id = bvh.prim_indices[s];
            if (id >= n || seen[id]++) __builtin_trap();
        }
    }
    for (const std::uint8_t s : seen) {
        if (s != 1) __builtin_trap();
    }
}

/// Closest hit t over the binary tree (or the linear scan when bvh is null), -1 for none.
float closest(const std::vector<Triangle>& tris, const Bvh* bvh, Ray ray, bool any_hit) {
    const WatertightRay w = prepare_watertight(ray);
    float best = -1.0f;
    auto slot = [&](std::uint32_t s, Ray& r) {
        const std::uint32_t id = bvh ? bvh->prim_indices[s] : s;
        const auto hit = intersect(tris[id], w, r.t_min, r.t_max);
        if (!hit) return false;
        r.t_max = hit->t;
        best = hit->t;
        return true;
    };
    const bool found =
        bvh ? (any_hit ? traverse<true>(*bvh, ray, slot) : traverse<false>(*bvh, ray, slot))
            : (any_hit ? traverse_linear<true>(std::uint32_t(tris.size()), ray, slot)
                       : traverse_linear<false>(std::uint32_t(tris.size()), ray, slot));
    return found ? best : -1.0f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    SahConfig sah;
    sah.bin_count = 2u + (data[0] & 31u) * 8u;  // 2 to 250 bins
    sah.max_leaf_size = 1u + (data[0] >> 5);    // 1 to 8
    std::vector<Triangle> tris;
    for (std::size_t at = 1; at + 36 <= size && tris.size() < 64; at += 36) {
        Triangle t;
        glm::vec3* corners[3] = {&t.p0, &t.p1, &t.p2};
        for (int k = 0; k < 3; ++k) {
            *corners[k] = {float_at(data + at + 12 * k), float_at(data + at + 12 * k + 4),
                           float_at(data + at + 12 * k + 8)};
        }
        tris.push_back(t);
    }
    if (tris.empty()) return 0;

    std::vector<BBox> boxes;
    std::vector<glm::vec3> centres;
    bool all_finite = true, in_range = true;
    const float range = kMaxMeshCoordinate / 4.0f;
    for (const Triangle& t : tris) {
        boxes.push_back(bounds(t));
        centres.push_back(boxes.back().center());
        all_finite = all_finite && finite(t.p0) && finite(t.p1) && finite(t.p2);
        const BBox& b = boxes.back();
        in_range =
            in_range && std::max({-b.lo.x, -b.lo.y, -b.lo.z, b.hi.x, b.hi.y, b.hi.z}) <= range;
    }
    // The binary builders: a clean tree or a librt::Error, never anything else.
    std::vector<Bvh> trees;
    for (int b = 0; b < 3; ++b) {
        try {
            trees.push_back(b == 0   ? build_median_bvh(boxes, centres)
                            : b == 1 ? build_sah_bvh(boxes, centres, sah)
                                     : build_sah_bvh(boxes, centres));
            check_tree(trees.back(), tris.size());
        } catch (const Error&) {
            if (all_finite) __builtin_trap();  // finite triangles have finite boxes and centres
        }
    }
    if (!all_finite) {
        // TriangleBvh refuses non-finite corners with an Error.
        try {
            (void)TriangleBvh(tris, BvhBuilder::Sah);
            __builtin_trap();
        } catch (const Error&) {
        }
        return 0;
    }

    const TriangleBvh wide_median(tris, BvhBuilder::Median);
    const TriangleBvh wide_sah(tris, BvhBuilder::Sah);
    const TriangleList list(tris);
    // Rays: from outside the scene's box to each triangle's centroid and to the box centre,
    // along a few directions.
    BBox scene;
    for (const BBox& b : boxes) scene.extend(b);
    std::vector<glm::vec3> targets{scene.center()};
    for (std::size_t i = 0; i < tris.size() && targets.size() < 16; ++i) {
        targets.push_back(centroid(tris[i]));
    }
    const float reach = glm::length(scene.diagonal());
    std::vector<Ray> stream;  // every ray traced below, for the stream queries at the end
    for (const glm::vec3& target : targets) {
        // Oblique directions are compared with the linear scan; axis-parallel ones only run.
        // (An axis-parallel ray's zero component is replaced by 1e-30 in the slab test, so it
        // drifts by 1e-30 t and can miss a box thinner than that which the scan's triangle
        // test hits: found by this target, see docs/robustness.md.)
        for (const glm::vec3 dir : {glm::normalize(glm::vec3(0.3f, -0.7f, 0.5f)),
                                    glm::normalize(glm::vec3(-0.6f, 0.2f, -0.4f)),
                                    glm::normalize(glm::vec3(0.5f, 0.5f, 0.7f)),
                                    glm::vec3(0, 0, -1), glm::vec3(1, 0, 0)}) {
            Ray ray;
            ray.direction = dir;
            ray.origin = target - dir * (std::isfinite(reach) ? reach + 1.0f : 1e30f);
            if (!finite(ray.origin)) continue;
            stream.push_back(ray);
            const float truth = closest(tris, nullptr, ray, false);
            const bool truth_any = closest(tris, nullptr, ray, true) >= 0.0f;
            const bool oblique = dir.x != 0.0f && dir.y != 0.0f && dir.z != 0.0f;
            if (!in_range || !oblique) {
                // Outside the representable range only "no crash" is promised.
                for (const Bvh& tree : trees) (void)closest(tris, &tree, ray, false);
                (void)wide_median.intersect(ray);
                (void)wide_sah.occluded(ray);
                continue;
            }
            if ((truth >= 0.0f) != truth_any) __builtin_trap();
            // A walk finds a hit exactly when the scan does, never a nearer one than the scan's;
            // an equal t is not asserted: pruning by an entry distance rounded up by an ulp can
            // skip a box whose hit ties the nearest within rounding (found by this target on
            // coplanar stacks of triangles with denormal coordinates; see docs/robustness.md).
            for (const Bvh& tree : trees) {
                const float t = closest(tris, &tree, ray, false);
                if ((t >= 0.0f) != (truth >= 0.0f) || t < truth) __builtin_trap();
                if ((closest(tris, &tree, ray, true) >= 0.0f) != truth_any) __builtin_trap();
            }
            const PrimitiveHit scan = list.intersect(ray);
            if (scan.valid() != (truth >= 0.0f) ||
                (scan.valid() && scan.t != truth)) {  // same test
                __builtin_trap();
            }
            for (const TriangleBvh* bvh : {&wide_median, &wide_sah}) {
                const PrimitiveHit hit = bvh->intersect(ray);
                if (hit.valid() != scan.valid() || (hit.valid() && hit.t < scan.t)) {
                    __builtin_trap();
                }
                if (bvh->occluded(ray) != scan.valid()) __builtin_trap();
            }
        }
    }
    for (const TriangleBvh* bvh : {&wide_median, &wide_sah}) {
        std::vector<PrimitiveHit> hits(stream.size());
        std::vector<std::uint8_t> blocked(stream.size());
        bvh->intersect(stream, hits);
        bvh->occluded(stream, blocked);
        for (std::size_t i = 0; i < stream.size(); ++i) {
            const PrimitiveHit one = bvh->intersect(stream[i]);
            if (std::memcmp(&one, &hits[i], sizeof one) != 0) __builtin_trap();
            if (blocked[i] != (bvh->occluded(stream[i]) ? 1 : 0)) __builtin_trap();
        }
    }
    return 0;
}
