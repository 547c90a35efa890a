// Issue 10, defect 1: the binned SAH builder turned a tiny positive centroid extent into an
// infinite bin scale, and the NaN / inf bin position into an out-of-range int bin index
// (INT_MIN), which it then used to index its bins: a crash (rt_synthesis --mesh on two
// triangles at x = 0 and x = 1e-40), or a heap overflow under ASan on geometry shrinking by
// powers of two into the denormals. Each case here must build and agree with the linear scan.

#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <utility>
#include <vector>

using namespace librt;

namespace {

std::vector<BBox> boxes_of(std::span<const Triangle> tris) {
    std::vector<BBox> boxes;
    for (const Triangle& t : tris) boxes.push_back(bounds(t));
    return boxes;
}

std::vector<glm::vec3> centres_of(std::span<const BBox> boxes) {
    std::vector<glm::vec3> centres;
    for (const BBox& b : boxes) centres.push_back(b.center());
    return centres;
}

/// Every slot of the tree's leaves holds each primitive exactly once.
void expect_permutation(const Bvh& bvh, std::size_t n) {
    std::vector<int> seen(n, 0);
    ASSERT_EQ(bvh.prim_indices.size(), n);
    for (const std::uint32_t id : bvh.prim_indices) {
        ASSERT_LT(id, n);
        ++seen[id];
    }
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "primitive " << i;
}

/// Rays towards the triangles from a few directions: TriangleBvh must find the linear
/// scan's hits (same t, same triangle unless two tie at the same t).
void expect_same_hits(std::span<const Triangle> tris, glm::vec3 target, float distance) {
    for (const BvhBuilder builder : {BvhBuilder::Sah, BvhBuilder::Median}) {
        const TriangleBvh bvh(tris, builder);
        const TriangleList list(tris);
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        for (int i = 0; i < 200; ++i) {
            glm::vec3 d{u(rng), u(rng), u(rng)};
            if (glm::length(d) < 0.1f) continue;
            d = glm::normalize(d);
            Ray ray;
            ray.origin = target - distance * d;
            ray.direction = d;
            const PrimitiveHit a = bvh.intersect(ray);
            const PrimitiveHit b = list.intersect(ray);
            ASSERT_EQ(a.valid(), b.valid()) << "ray " << i;
            if (a.valid()) {
                EXPECT_EQ(a.t, b.t) << "ray " << i;
            }
            EXPECT_EQ(bvh.occluded(ray), b.valid()) << "ray " << i;
        }
    }
}

}  // namespace

TEST(BvhBinning, CentroidsADenormalApartBuildAndAreHit) {
    // The reproducer: one triangle in the plane x = 0, one in x = 1e-40.
    const float tiny = 1e-40f;
    ASSERT_GT(tiny, 0.0f);
    const std::vector<Triangle> tris = {
        {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}},
        {{tiny, 0, 0}, {tiny, 1, 0}, {tiny, 0, 1}},
    };
    const std::vector<BBox> boxes = boxes_of(tris);
    const std::vector<glm::vec3> centres = centres_of(boxes);
    ASSERT_GT(centres[1].x - centres[0].x, 0.0f);  // a positive, denormal extent
    for (const std::uint32_t bins : {2u, 4u, 32u, 256u}) {
        SahConfig config;
        config.bin_count = bins;
        config.max_leaf_size = 1;  // force the split that bins the two centres
        const Bvh bvh = build_sah_bvh(boxes, centres, config);
        expect_permutation(bvh, tris.size());
        EXPECT_GE(bvh.nodes.size(), 3u) << "the two centres are distinct: a split exists";
    }
    expect_same_hits(tris, {0.0f, 0.25f, 0.25f}, 5.0f);
}

TEST(BvhBinning, GeometryShrinkingByPowersOfTwoIntoTheDenormals) {
    // Triangle k at x = 2^-k (k up to 149, the smallest denormal), each a unit square's
    // half in y, z: every level's centroid extent shrinks by two until it is denormal.
    std::vector<Triangle> tris;
    for (int k = 0; k <= 149; ++k) {
        const float x = std::ldexp(1.0f, -k);
        tris.push_back({{x, 0, 0}, {x, 1, 0}, {x, 0, 1}});
    }
    tris.push_back({{0, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    const std::vector<BBox> boxes = boxes_of(tris);
    const std::vector<glm::vec3> centres = centres_of(boxes);
    SahConfig config;
    config.max_leaf_size = 1;
    const Bvh bvh = build_sah_bvh(boxes, centres, config);
    expect_permutation(bvh, tris.size());
    EXPECT_LE(bvh.depth, kMaxBvhDepth);
    expect_same_hits(tris, {0.5f, 0.25f, 0.25f}, 5.0f);
}

namespace {

/// Builds per_side unit boxes at x = a and per_side at x = b (the centres differ in x only,
/// so the root splits in x) and expects the root's two children to hold one side each.
void expect_root_separates(float a, float b, int per_side) {
    std::vector<BBox> boxes;
    std::vector<glm::vec3> centres;
    for (int i = 0; i < 2 * per_side; ++i) {
        const float x = i < per_side ? a : b;
        boxes.push_back({{x, 0, 0}, {x, 1, 1}});
        centres.push_back({x, 0.5f, 0.5f});
    }
    SahConfig config;
    config.max_leaf_size = 1;
    const Bvh bvh = build_sah_bvh(boxes, centres, config);
    expect_permutation(bvh, boxes.size());
    const BvhNode& root = bvh.nodes[0];
    ASSERT_FALSE(root.is_leaf());
    for (int c = 0; c < 2; ++c) {
        const BBox& box = bvh.nodes[root.index + c].bounds;
        EXPECT_EQ(box.lo.x, box.hi.x)
            << "gap " << a << ".." << b << ", child " << c << " mixes the two sides";
    }
}

}  // namespace

TEST(BvhBinning, CentroidExtentOverflowingFloatStillSplits) {
    // Centres at -3e38 and +3e38: hi - lo overflows to inf in float (the scale was then 0
    // and (c - lo) * 0 NaN); the split must still separate them.
    expect_root_separates(-3e38f, 3e38f, 2);
}

TEST(BvhBinning, LargeNodesPartitionByThresholdOnHardCentres) {
    // Nodes of 128 or more primitives are partitioned by a threshold found by bisection on
    // the floats (the bin test's least centre of the split bin): it must send each centre
    // where its bin does, here with 100 centres on each side of a denormal gap and of a gap
    // whose extent overflows float.
    expect_root_separates(0.0f, 1e-40f, 100);
    expect_root_separates(-3e38f, 3e38f, 100);
}
