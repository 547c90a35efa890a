// A flat top level of spheres only tests every sphere at once (SIMD, src/accel/sphere_roots.h)
// instead of visiting the boxes nearest first; these tests hold every SIMD path to the Scalar
// path's hits (one sphere at a time as each box is visited, what TopLevel always did) bit for
// bit, ties between touching or coincident spheres included.

#include <librt/accel/simd.h>
#include <librt/accel/top_level.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

namespace librt {
namespace {

struct DSphere {
    glm::dvec3 c;
    double r;
};

// smallpt's room (walls of radius 1e5 given in double, the radius-600 light's cap through
// the ceiling), plus spheres that touch, nest, and coincide (every ray that meets the
// coincident pair is a tie the box order must decide).
std::vector<DSphere> room() {
    return {
        {{1e5 + 1, 40.8, 81.6}, 1e5},
        {{-1e5 + 99, 40.8, 81.6}, 1e5},
        {{50, 40.8, 1e5}, 1e5},
        {{50, 40.8, -1e5 + 170}, 1e5},
        {{50, 1e5, 81.6}, 1e5},
        {{50, -1e5 + 81.6, 81.6}, 1e5},
        {{27, 16.5, 47}, 16.5},
        {{73, 16.5, 78}, 16.5},
        {{50, 681.6 - 0.27, 81.6}, 600},
        {{50, 30, 60}, 8},
        {{50, 30, 60}, 8},
        {{66, 30, 60}, 8},  // touches the one before
        {{50, 60, 100}, 10},
        {{50, 60, 100}, 4},  // nested
    };
}

TopLevel make(const std::vector<DSphere>& spheres) {
    TopLevel top;
    for (const DSphere& s : spheres) top.add_sphere(s.c, s.r, false);
    top.build();
    return top;
}

TEST(SphereList, EverySimdPathFindsTheBoxOrderHits) {
    const std::vector<DSphere> spheres = room();
    TopLevel reference = make(spheres);
    reference.set_simd_path(SimdPath::Scalar);
    TopLevel fast = make(spheres);
    std::mt19937 rng(15);
    std::uniform_real_distribution<float> in_room(1.0f, 99.0f), depth(0.0f, 170.0f),
        dir(-1.0f, 1.0f), unit(0.0f, 1.0f);
    const auto paths = supported_simd_paths();
    ASSERT_GT(paths.size(), 1u) << "no SIMD path to compare with Scalar";
    for (const SimdPath path : paths) {
        if (path == SimdPath::Scalar) continue;
        fast.set_simd_path(path);
        ASSERT_EQ(fast.simd_path(), path);
        int hits = 0, occluded = 0, tied = 0;
        for (int i = 0; i < 40000; ++i) {
            Ray ray;
            if (i % 4 == 0) {
                // Aimed at a point of the coincident or touching pair: many ties.
                ray.origin = {in_room(rng), in_room(rng) * 0.8f, depth(rng)};
                const glm::vec3 target{58.0f + 0.001f * dir(rng), 30.0f + 8.0f * dir(rng),
                                       60.0f + 8.0f * dir(rng)};
                ray.direction = target - ray.origin;
            } else {
                ray.origin = i % 4 == 1 ? glm::vec3(dir(rng), dir(rng), dir(rng)) * 2000.0f
                                        : glm::vec3(in_room(rng), in_room(rng) * 0.8f, depth(rng));
                ray.direction = {dir(rng), dir(rng), dir(rng)};
            }
            if (i % 3 == 0) ray.t_min = 5.0f * unit(rng);
            if (i % 5 == 0) ray.t_max = 200.0f * unit(rng);
            ObjectHit want, got;
            const bool hit_want = reference.intersect(ray, want);
            const bool hit_got = fast.intersect(ray, got);
            ASSERT_EQ(hit_want, hit_got) << "ray " << i << " path " << to_string(path);
            if (hit_want) {
                ++hits;
                ASSERT_EQ(want.object_id, got.object_id) << "ray " << i;
                ASSERT_EQ(std::bit_cast<std::uint32_t>(want.primitive.t),
                          std::bit_cast<std::uint32_t>(got.primitive.t))
                    << "ray " << i;
                tied += want.object_id == 9 || want.object_id == 10;
            }
            // Any-hit, with and without an object left out (a light's own sphere, say).
            const std::uint32_t ignored = i % 2 ? std::uint32_t(i % 14) : kInvalidId;
            const bool occ = reference.occluded(ray, ignored);
            ASSERT_EQ(occ, fast.occluded(ray, ignored)) << "ray " << i;
            occluded += occ;
        }
        // The rays exercised what they were meant to (not a vacuous agreement).
        EXPECT_GT(hits, 20000);
        EXPECT_GT(tied, 1000);
        EXPECT_GT(occluded, 20000);
    }
}

// A ray with a NaN or zero direction, or an empty interval, misses on every path.
TEST(SphereList, UntraceableRaysMiss) {
    TopLevel top = make(room());
    for (const SimdPath path : supported_simd_paths()) {
        top.set_simd_path(path);
        Ray nan_ray;
        nan_ray.origin = {50, 40, 80};
        nan_ray.direction = {std::nanf(""), 0, 1};
        Ray zero = nan_ray;
        zero.direction = glm::vec3(0.0f);
        Ray empty = nan_ray;
        empty.direction = {0, 1, 0};
        empty.t_min = 2.0f;
        empty.t_max = 1.0f;
        for (const Ray& r : {nan_ray, zero, empty}) {
            ObjectHit h;
            EXPECT_FALSE(top.intersect(r, h));
            EXPECT_FALSE(top.occluded(r));
        }
    }
}

}  // namespace
}  // namespace librt
