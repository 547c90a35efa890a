// The BVH against the linear scan on real and procedural meshes: both builders must
// return exactly the scan's nearest t (ties aside) and the same any-hit answer.

#include "ray_sets.h"
#include "test_support.h"

#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/procedural.h>
#include <librt/obj/obj.h>

#include <gtest/gtest.h>

#include <thread>
#include <vector>

using namespace librt;

namespace {

/// Linear-scan answers, spread over two threads (the scan is the slow part).
std::vector<PrimitiveHit> scan_hits(const TriangleList& naive, const std::vector<Ray>& rays) {
    std::vector<PrimitiveHit> hits(rays.size());
    auto work = [&](std::size_t begin, std::size_t step) {
        for (std::size_t i = begin; i < rays.size(); i += step) hits[i] = naive.intersect(rays[i]);
    };
    std::thread other(work, 1, 2);
    work(0, 2);
    other.join();
    return hits;
}

void expect_bvh_matches_scan(const TriangleMesh& mesh, std::size_t ray_count, std::uint32_t seed) {
    const auto rays = librt::testing::incoherent_rays(mesh.bounds(), ray_count, seed);
    const auto expected = scan_hits(TriangleList(mesh), rays);
    for (const BvhBuilder builder : {BvhBuilder::Median, BvhBuilder::Sah}) {
        SCOPED_TRACE(builder == BvhBuilder::Median ? "median" : "sah");
        const TriangleBvh accel(mesh, builder);
        std::size_t closest_wrong = 0, any_wrong = 0, hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PrimitiveHit got = accel.intersect(rays[i]);
            const PrimitiveHit& want = expected[i];
            hits += want.valid();
            bool same = got.valid() == want.valid() && (!want.valid() || got.t == want.t);
            if (same && want.valid() && got.primitive_id != want.primitive_id) {
                const auto tie = intersect(mesh.triangle(got.primitive_id), rays[i]);
                same = tie && tie->t == want.t;
            }
            closest_wrong += !same;
            any_wrong += accel.occluded(rays[i]) != want.valid();
        }
        EXPECT_EQ(closest_wrong, 0u);
        EXPECT_EQ(any_wrong, 0u);
        EXPECT_GT(hits, rays.size() / 5);  // the set must hit and miss
        EXPECT_LT(hits, rays.size());
    }
}

}  // namespace

TEST(BvhMesh, TeapotAgreesWithLinearScanOn100kRays) {
    expect_bvh_matches_scan(make_teapot(4), 100'000, 11);  // 1,024 triangles
}

TEST(BvhMesh, IcosphereAgreesWithLinearScanOn100kRays) {
    expect_bvh_matches_scan(make_icosphere(glm::vec3(0.0f), 1.0f, 3), 100'000, 12);
}

TEST(BvhMesh, BunnyAtOriginalScaleAgreesWithLinearScanOn10kRays) {
    LIBRT_REQUIRE_DATA_FILE(path, "stanford-bunny.obj");
    const TriangleMesh bunny = load_obj(path);
    ASSERT_EQ(bunny.triangle_count(), 69'451u);
    // Kept at its tiny original scale (about 0.15 across) on purpose.
    expect_bvh_matches_scan(bunny, 10'000, 13);
}
