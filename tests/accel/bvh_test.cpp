#include "ray_sets.h"
#include "triangle_sets.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace librt;
using librt::testing::incoherent_rays;
using librt::testing::random_soup;

namespace {

/// Checks the structural invariants every builder must keep.
void check_structure(const Bvh& bvh, std::span<const Triangle> tris, std::uint32_t max_leaf,
                     bool median_split) {
    ASSERT_FALSE(bvh.empty());
    ASSERT_LE(bvh.depth, kMaxBvhDepth);
    std::vector<int> seen(tris.size(), 0);
    for (const std::uint32_t id : bvh.prim_indices) {
        ASSERT_LT(id, tris.size());
        seen[id]++;
    }
    for (const int s : seen) ASSERT_EQ(s, 1) << "every primitive must sit in exactly one slot";
    std::size_t leaf_prims = 0;
    for (const BvhNode& node : bvh.nodes) {
        if (node.is_leaf()) {
            leaf_prims += node.prim_count;
            if (node.prim_count > max_leaf) {
                // Only the report's rule may leave a big leaf: every centroid on one side
                // of the plane through the box centre on its longest axis.
                ASSERT_TRUE(median_split) << "SAH leaf of " << node.prim_count;
                const int axis = node.bounds.largest_axis();
                const float plane = node.bounds.center()[axis];
                int below = 0;
                for (std::uint32_t s = node.index; s < node.index + node.prim_count; ++s)
                    below += centroid(tris[bvh.prim_indices[s]])[axis] < plane;
                EXPECT_TRUE(below == 0 || below == int(node.prim_count));
            }
            for (std::uint32_t s = node.index; s < node.index + node.prim_count; ++s) {
                const BBox b = bounds(tris[bvh.prim_indices[s]]);
                ASSERT_TRUE(node.bounds.contains(b.lo) && node.bounds.contains(b.hi));
            }
        } else {
            ASSERT_LT(node.index + 1, bvh.nodes.size());
            for (const std::uint32_t child : {node.index, node.index + 1}) {
                const BBox& cb = bvh.nodes[child].bounds;
                ASSERT_TRUE(node.bounds.contains(cb.lo) && node.bounds.contains(cb.hi));
            }
        }
    }
    EXPECT_EQ(leaf_prims, tris.size());
}

/// The BVH must find exactly what the linear scan finds: the same t (the same
/// triangle test runs on the same ray), and the same triangle unless two tie at t.
void expect_agrees_with_linear_scan(std::span<const Triangle> tris, const std::vector<Ray>& rays,
                                    const std::vector<PrimitiveHit>& expected, BvhBuilder builder) {
    const TriangleBvh accel(tris, builder);
    std::size_t hits = 0, mismatches = 0, any_mismatches = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& ray = rays[i];
        const PrimitiveHit& want = expected[i];
        const PrimitiveHit got = accel.intersect(ray);
        hits += want.valid();
        bool same = want.valid() == got.valid() && (!want.valid() || want.t == got.t);
        if (same && want.valid() && want.primitive_id != got.primitive_id) {
            // A tie: the other triangle must be hit at exactly the same t.
            const auto h = intersect(tris[got.primitive_id], ray);
            same = h && h->t == want.t;
        }
        mismatches += !same;
        any_mismatches += accel.occluded(ray) != want.valid();
    }
    EXPECT_EQ(mismatches, 0u) << "closest-hit disagreements out of " << rays.size();
    EXPECT_EQ(any_mismatches, 0u) << "any-hit disagreements out of " << rays.size();
    // The ray set must exercise both outcomes for the comparison to mean anything.
    EXPECT_GT(hits, rays.size() / 10);
    EXPECT_LT(hits, rays.size());
}

std::vector<PrimitiveHit> linear_scan_hits(std::span<const Triangle> tris,
                                           const std::vector<Ray>& rays) {
    const TriangleList naive(tris);
    std::vector<PrimitiveHit> hits(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = naive.intersect(rays[i]);
    return hits;
}

}  // namespace

TEST(BvhBuilder, EmptyInputGivesEmptyBvh) {
    const Bvh bvh = build_sah_bvh({}, {});
    EXPECT_TRUE(bvh.empty());
    Ray r;
    EXPECT_FALSE(TriangleBvh(std::span<const Triangle>{}).intersect(r).valid());
    EXPECT_FALSE(TriangleBvh(std::span<const Triangle>{}).occluded(r));
}

TEST(BvhBuilder, MismatchedOrNonFiniteInputThrows) {
    const std::vector<BBox> boxes(2, BBox{{0, 0, 0}, {1, 1, 1}});
    std::vector<glm::vec3> centers(1, glm::vec3(0.5f));
    EXPECT_THROW((void)build_sah_bvh(boxes, centers), Error);
    centers = {glm::vec3(0.5f), glm::vec3(NAN, 0, 0)};
    EXPECT_THROW((void)build_sah_bvh(boxes, centers), Error);
    EXPECT_THROW((void)build_median_bvh(boxes, centers), Error);
}

TEST(BvhBuilder, MedianAndSahKeepInvariants) {
    const auto tris = random_soup(5000, 1);
    std::vector<BBox> boxes;
    std::vector<glm::vec3> centers;
    for (const Triangle& t : tris) {
        boxes.push_back(bounds(t));
        centers.push_back(centroid(t));
    }
    check_structure(build_median_bvh(boxes, centers), tris, 5, true);
    check_structure(build_sah_bvh(boxes, centers), tris, SahConfig{}.max_leaf_size, false);
}

TEST(BvhBuilder, IdenticalCentroidsStillGiveSmallLeavesWithSah) {
    // 1000 copies of one triangle: no plane separates them, SAH must still bound leaves.
    const std::vector<Triangle> tris(1000, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const TriangleBvh accel(tris, BvhBuilder::Sah);
    EXPECT_LE(accel.stats().max_leaf_size, SahConfig{}.max_leaf_size);
    Ray r;
    r.origin = {0.2f, 0.2f, 1.0f};
    EXPECT_TRUE(accel.intersect(r).valid());
}

TEST(BvhTraversal, AgreesWithLinearScanOnRandomSoup) {
    const auto tris = random_soup(1000, 2);
    const auto rays = incoherent_rays(BBox{glm::vec3(0.0f), glm::vec3(1.0f)}, 100000, 3);
    const auto expected = linear_scan_hits(tris, rays);
    expect_agrees_with_linear_scan(tris, rays, expected, BvhBuilder::Median);
    expect_agrees_with_linear_scan(tris, rays, expected, BvhBuilder::Sah);
}

TEST(BvhTraversal, AxisParallelRaysThroughAGridHaveNoHoles) {
    // A flat grid of quads at z = 0 with rays exactly along -z through every inner grid
    // line: box faces coincide with the rays, which must still find a triangle. (On the
    // grid's outer rim a ray lying in the root box's face counts as outside, see bbox.h.)
    const int n = 16;
    const std::vector<Triangle> tris = librt::testing::unit_grid(n);
    for (const BvhBuilder builder : {BvhBuilder::Median, BvhBuilder::Sah}) {
        const TriangleBvh accel(tris, builder);
        int holes = 0;
        for (int i = 0; i < 4 * n; ++i)
            for (int j = 0; j < 4 * n; ++j) {
                Ray r;
                r.origin = {float(i) * 0.25f, float(j) * 0.25f, 5.0f};
                r.direction = {0.0f, 0.0f, -1.0f};
                if (!accel.intersect(r).valid()) ++holes;
                if (!accel.occluded(r)) ++holes;
            }
        EXPECT_EQ(holes, 0);
    }
}

TEST(BvhTraversal, NanAndZeroDirectionRaysMiss) {
    const auto tris = random_soup(100, 4);
    const TriangleBvh accel(tris);
    Ray r;
    r.origin = {0.5f, 0.5f, 0.5f};
    r.direction = {0.0f, 0.0f, 0.0f};
    EXPECT_FALSE(accel.intersect(r).valid());
    EXPECT_FALSE(accel.occluded(r));
    r.direction = {NAN, 0.0f, 1.0f};
    EXPECT_FALSE(accel.intersect(r).valid());
    r.direction = {0.0f, 0.0f, 1.0f};
    r.origin = {NAN, 0.5f, 0.5f};
    EXPECT_FALSE(accel.occluded(r));
}
