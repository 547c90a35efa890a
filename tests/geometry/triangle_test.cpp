#include <librt/geometry/triangle.h>

#include <gtest/gtest.h>

#include <random>

using namespace librt;

namespace {
const Triangle kTri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
}  // namespace

TEST(Triangle, InteriorHitGivesTAndBarycentrics) {
    const auto h = intersect(kTri, Ray{{0.25f, 0.5f, 3}, {0, 0, -1}});
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 3.0f);
    EXPECT_FLOAT_EQ(h->u, 0.25f);
    EXPECT_FLOAT_EQ(h->v, 0.5f);
}

TEST(Triangle, BothFacesHit) {
    EXPECT_TRUE(intersect(kTri, Ray{{0.2f, 0.2f, 3}, {0, 0, -1}}));
    EXPECT_TRUE(intersect(kTri, Ray{{0.2f, 0.2f, -3}, {0, 0, 1}}));
}

TEST(Triangle, OutsideMisses) {
    EXPECT_FALSE(intersect(kTri, Ray{{0.6f, 0.6f, 3}, {0, 0, -1}}));
    EXPECT_FALSE(intersect(kTri, Ray{{-0.01f, 0.5f, 3}, {0, 0, -1}}));
}

TEST(Triangle, EdgesAndVerticesCountAsHits) {
    EXPECT_TRUE(intersect(kTri, Ray{{0.5f, 0.0f, 1}, {0, 0, -1}}));  // edge p0-p1
    EXPECT_TRUE(intersect(kTri, Ray{{0.5f, 0.5f, 1}, {0, 0, -1}}));  // edge p1-p2
    EXPECT_TRUE(intersect(kTri, Ray{{0.0f, 0.0f, 1}, {0, 0, -1}}));  // vertex p0
    EXPECT_TRUE(intersect(kTri, Ray{{1.0f, 0.0f, 1}, {0, 0, -1}}));  // vertex p1
}

TEST(Triangle, ParallelRayMisses) {
    EXPECT_FALSE(intersect(kTri, Ray{{-1, 0.2f, 0}, {1, 0, 0}}));  // in plane
    EXPECT_FALSE(intersect(kTri, Ray{{-1, 0.2f, 1}, {1, 0, 0}}));  // above plane
}

TEST(Triangle, BehindOriginAndTRangeMiss) {
    EXPECT_FALSE(intersect(kTri, Ray{{0.2f, 0.2f, 3}, {0, 0, 1}}));
    Ray r = Ray{{0.2f, 0.2f, 3}, {0, 0, -1}};
    r.t_max = 2.5f;
    EXPECT_FALSE(intersect(kTri, r));
}

TEST(Triangle, TinyScaleStillHits) {
    // The shared bunny is ~0.15 across: no absolute determinant threshold may reject it.
    const float s = 1e-4f;
    const Triangle tiny{{0, 0, 0}, {s, 0, 0}, {0, s, 0}};
    EXPECT_TRUE(intersect(tiny, Ray{{0.25f * s, 0.25f * s, 1}, {0, 0, -1}}));
}

TEST(Triangle, SharedEdgeIsWatertight) {
    // Two triangles sharing the diagonal edge of a quad, with awkward coordinates.
    const glm::vec3 a{0.1f, 0.3f, -2.0f}, b{1.7f, 0.2f, -2.3f}, c{1.3f, 1.9f, -1.7f},
        d{0.2f, 1.4f, -2.1f};
    const Triangle t1{a, b, c}, t2{a, c, d};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    int misses = 0;
    for (int i = 0; i < 20000; ++i) {
        // Origins all around; aim exactly at a float point on the shared edge a-c.
        const glm::vec3 o{U(rng) * 4 - 2, U(rng) * 4 - 2, U(rng) * 3 + 1};
        const float s = U(rng);
        const glm::vec3 target = a + s * (c - a);
        const Ray r = Ray{o, target - o};
        if (!intersect(t1, r) && !intersect(t2, r)) ++misses;
    }
    EXPECT_EQ(misses, 0);
}

TEST(Triangle, DegenerateTriangleNeverHits) {
    const Triangle line{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}};
    EXPECT_FALSE(intersect(line, Ray{{1, 1, 1}, {0, 0, -1}}));
}
