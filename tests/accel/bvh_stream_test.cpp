// TriangleBvh's ray streams (intersect(rays, hits), occluded(rays, blocked)) against its
// single-ray queries: the same answer for every ray, bit for bit, on every SIMD path, for
// incoherent and coherent rays over real meshes and for the rays the single path treats
// specially (untraceable, empty intervals, origins beyond the AVX kernels' range).
//
// A stream takes the interleaved walk (wide_stream.h) only over a tree of 8 MiB or more and
// when its first rays are not coherent (interleave_stream in triangle_bvh.cpp); otherwise it
// loops over the single-ray query. So the dragon (a ~48 MB tree) and a 200k-triangle teapot
// (~11 MB) take the walk, the coherent and odd rays are also streamed behind a few
// incoherent ones, and the bunny (~3.9 MB) and a small teapot cover the loop.

#include "ray_sets.h"
#include "test_support.h"

#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/obj/obj.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

using namespace librt;

namespace {

/// The bits of a hit, so that equality means bit for bit (a NaN or -0 would not hide).
struct HitBits {
    std::uint32_t t, u, v, id;
    bool operator==(const HitBits&) const = default;
};

HitBits bits(const PrimitiveHit& h) {
    return {std::bit_cast<std::uint32_t>(h.t), std::bit_cast<std::uint32_t>(h.u),
            std::bit_cast<std::uint32_t>(h.v), h.primitive_id};
}

/// On every supported SIMD path: both streams over `rays` give the single-ray answers ray by
/// ray. Returns the number of closest hits (the same on every path), so callers can check the
/// rays hit and miss.
std::size_t expect_streams_match_single_rays(TriangleBvh& accel, const std::vector<Ray>& rays) {
    std::size_t hit_count = 0;
    for (const SimdPath path : supported_simd_paths()) {
        SCOPED_TRACE(to_string(path));
        accel.set_simd_path(path);
        // Filled with a value no query writes, so a ray the stream skipped would show.
        std::vector<PrimitiveHit> hits(rays.size(), PrimitiveHit{-1.0f, -1.0f, -1.0f, 7u});
        std::vector<std::uint8_t> blocked(rays.size(), 2);
        accel.intersect(rays, hits);
        accel.occluded(rays, blocked);
        std::size_t closest_wrong = 0, any_wrong = 0, hits_here = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PrimitiveHit want = accel.intersect(rays[i]);
            hits_here += want.valid();
            if (!(bits(hits[i]) == bits(want))) {
                if (closest_wrong == 0)
                    ADD_FAILURE() << "ray " << i << ": stream t " << hits[i].t << " id "
                                  << hits[i].primitive_id << ", single t " << want.t << " id "
                                  << want.primitive_id;
                ++closest_wrong;
            }
            any_wrong += blocked[i] != (accel.occluded(rays[i]) ? 1 : 0);
        }
        EXPECT_EQ(closest_wrong, 0u);
        EXPECT_EQ(any_wrong, 0u);
        if (path != supported_simd_paths().front()) {
            EXPECT_EQ(hits_here, hit_count);
        }
        hit_count = hits_here;
    }
    return hit_count;
}

/// Streams of every length up to 9 (more and fewer rays than the lanes walked at once) and a
/// stream of rays the single path answers without a walk or with an empty interval, mixed
/// with ordinary ones (first) so that the interleaved walk's lanes refill around them.
void expect_short_and_odd_streams_match(TriangleBvh& accel, const BBox& box) {
    const auto base = librt::testing::incoherent_rays(box, 64, 54);
    for (std::size_t n = 0; n <= 9; ++n) {
        SCOPED_TRACE("length " + std::to_string(n));
        expect_streams_match_single_rays(accel, std::vector<Ray>(base.begin(), base.begin() + n));
    }
    // Rays the single path answers without a walk, or with an empty interval, mixed with
    // ordinary ones so that the stream's lanes refill around them.
    std::vector<Ray> odd;
    for (std::size_t i = 0; i < base.size(); ++i) {
        Ray r = base[i];
        switch (i % 8) {
            case 7:
                r.t_max = 0.0f;
                break;  // empty (0, 0)
            case 1:
                r.t_max = NAN;
                break;  // not traceable
            case 2:
                r.t_min = NAN;
                break;  // not traceable
            case 3:
                r.direction = glm::vec3(0.0f);
                break;  // not traceable
            case 4:
                r.origin.x = NAN;
                break;  // not traceable
            case 5:     // t_min > t_max
                r.t_min = 2.0f;
                r.t_max = 1.0f;
                break;
            case 6:  // beyond the AVX kernels' range (slab8_avx.h), still aimed at the mesh
                r.origin -= r.direction * (1e8f / glm::length(r.direction));
                break;
            default:
                break;  // 0: an ordinary ray (the first is one)
        }
        odd.push_back(r);
    }
    expect_streams_match_single_rays(accel, odd);
    for (const SimdPath path : supported_simd_paths()) {
        accel.set_simd_path(path);
        std::vector<PrimitiveHit> hits(odd.size());
        accel.intersect(odd, hits);
        for (std::size_t i = 0; i < odd.size(); ++i)
            if (i % 8 >= 1 && i % 8 <= 5) {
                EXPECT_FALSE(hits[i].valid()) << i;
            }
    }
}

}  // namespace

namespace {

/// Incoherent and primary rays over a real mesh, the primary ones also behind four incoherent
/// rays (so that they take the interleaved walk when the tree is big enough).
void expect_real_mesh_streams_match(const TriangleMesh& mesh, std::size_t incoherent_count) {
    TriangleBvh accel(mesh);
    const auto incoherent = librt::testing::incoherent_rays(mesh.bounds(), incoherent_count, 51);
    const std::size_t hits = expect_streams_match_single_rays(accel, incoherent);
    EXPECT_GT(hits, incoherent.size() / 5);  // the set must hit and miss
    EXPECT_LT(hits, incoherent.size());
    // Coherent rays: a pinhole camera's, many grazing the silhouette.
    const auto primary = librt::testing::primary_rays(mesh.bounds(), 100, 100, 40.0f);
    const std::size_t primary_hits = expect_streams_match_single_rays(accel, primary);
    EXPECT_GT(primary_hits, primary.size() / 10);
    EXPECT_LT(primary_hits, primary.size());
    std::vector<Ray> mixed(incoherent.begin(), incoherent.begin() + 4);
    mixed.insert(mixed.end(), primary.begin(), primary.end());
    expect_streams_match_single_rays(accel, mixed);
}

}  // namespace

TEST(BvhStream, MatchesSingleRaysOnTheDragonIncoherentAndPrimary) {
    LIBRT_REQUIRE_DATA_FILE(path, "stanford-dragon.obj");
    const TriangleMesh dragon = load_obj(path);
    // The premise: past the interleaved walk's threshold.
    ASSERT_GE(TriangleBvh(dragon).memory_bytes(), std::size_t{8} << 20);
    expect_real_mesh_streams_match(dragon, 10000);
}

TEST(BvhStream, MatchesSingleRaysOnTheBunnyIncoherentAndPrimary) {
    LIBRT_REQUIRE_DATA_FILE(path, "stanford-bunny.obj");
    expect_real_mesh_streams_match(load_obj(path), 10000);
}

TEST(BvhStream, MatchesSingleRaysOnATeapotFromInsideAndOutside) {
    // Origins inside the mesh too (rays that hit several layers and must keep the nearest),
    // with random bounded intervals so that t_max culls deferred children.
    const TriangleMesh teapot = make_teapot_with_triangles(200000);
    TriangleBvh accel(teapot);
    ASSERT_GE(accel.memory_bytes(), std::size_t{8} << 20);  // the interleaved walk's threshold
    const BBox box = teapot.bounds();
    std::mt19937 rng(52);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Ray> rays = librt::testing::incoherent_rays(box, 8000, 53);
    for (int i = 0; i < 8000; ++i) {
        Ray r;
        r.origin = box.lo + glm::vec3(unit(rng), unit(rng), unit(rng)) * box.diagonal();
        r.direction = {unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f};
        r.t_min = i % 3 == 0 ? unit(rng) : 0.0f;
        r.t_max = i % 2 == 0 ? INFINITY : 10.0f * unit(rng);
        rays.push_back(r);
    }
    const std::size_t hits = expect_streams_match_single_rays(accel, rays);
    EXPECT_GT(hits, rays.size() / 5);
    EXPECT_LT(hits, rays.size());
}

TEST(BvhStream, EmptyAndShortStreamsAndRaysTheSinglePathRefuses) {
    for (const int triangles : {200000, 500}) {  // the interleaved walk, then the loop
        SCOPED_TRACE(std::to_string(triangles) + " triangles");
        const TriangleMesh teapot = make_teapot_with_triangles(triangles);
        TriangleBvh accel(teapot);
        // The premise: the big teapot's tree is past the interleaving threshold, the small
        // one's below it.
        EXPECT_EQ(accel.memory_bytes() >= (std::size_t{8} << 20), triangles == 200000);
        expect_short_and_odd_streams_match(accel, teapot.bounds());
    }
}

TEST(BvhStream, AnEmptyBvhMissesEveryRayOfAStream) {
    const TriangleBvh empty;
    const auto rays =
        librt::testing::incoherent_rays(BBox{glm::vec3(0.0f), glm::vec3(1.0f)}, 5, 55);
    std::vector<PrimitiveHit> hits(rays.size(), PrimitiveHit{1.0f, 0.0f, 0.0f, 3u});
    std::vector<std::uint8_t> blocked(rays.size(), 1);
    empty.intersect(rays, hits);
    empty.occluded(rays, blocked);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_FALSE(hits[i].valid());
        EXPECT_EQ(blocked[i], 0);
    }
}

TEST(BvhStream, MismatchedSizesThrowNamingBoth) {
    const TriangleBvh accel(make_teapot(2));
    const auto rays = librt::testing::incoherent_rays(accel.bounds(), 5, 56);
    std::vector<PrimitiveHit> hits(4);
    std::vector<std::uint8_t> blocked(6);
    try {
        accel.intersect(rays, hits);
        ADD_FAILURE() << "no error for 5 rays and 4 hits";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find('5'), std::string::npos) << what;
        EXPECT_NE(what.find('4'), std::string::npos) << what;
    }
    try {
        accel.occluded(rays, blocked);
        ADD_FAILURE() << "no error for 5 rays and 6 flags";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find('5'), std::string::npos) << what;
        EXPECT_NE(what.find('6'), std::string::npos) << what;
    }
    // The outputs are left as they were.
    for (const PrimitiveHit& h : hits) EXPECT_FALSE(h.valid());
    for (const std::uint8_t b : blocked) EXPECT_EQ(b, 0);
}
