#include <librt/geometry/sphere.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

using namespace librt;

TEST(Sphere, HitFromOutsideReturnsNearRoot) {
    const Sphere s{{0, 0, -10}, 2};
    const auto t = intersect(s, Ray{{0, 0, 0}, {0, 0, -1}});
    ASSERT_TRUE(t);
    EXPECT_FLOAT_EQ(*t, 8.0f);
}

TEST(Sphere, HitFromInsideReturnsFarRoot) {
    const Sphere s{{1, 2, 3}, 5};
    const auto t = intersect(s, Ray{{1, 2, 3}, {0, 1, 0}});
    ASSERT_TRUE(t);
    EXPECT_FLOAT_EQ(*t, 5.0f);
}

TEST(Sphere, BehindTheRayMisses) {
    const Sphere s{{0, 0, 10}, 2};
    EXPECT_FALSE(intersect(s, Ray{{0, 0, 0}, {0, 0, -1}}));
}

TEST(Sphere, TangentRayTouchesOnce) {
    const Sphere s{{0, 0, -10}, 1};
    const auto t = intersect(s, Ray{{1, 0, 0}, {0, 0, -1}});
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 10.0f, 1e-3f);
    EXPECT_FALSE(intersect(s, Ray{{1.001f, 0, 0}, {0, 0, -1}}));
}

TEST(Sphere, RespectsTRange) {
    const Sphere s{{0, 0, -10}, 2};
    Ray r = Ray{{0, 0, 0}, {0, 0, -1}};
    r.t_max = 7.0f;
    EXPECT_FALSE(intersect(s, r));
    r.t_max = 100.0f;
    r.t_min = 9.0f;  // skips the near root, keeps the far one
    const auto t = intersect(s, r);
    ASSERT_TRUE(t);
    EXPECT_FLOAT_EQ(*t, 12.0f);
}

TEST(Sphere, NonUnitDirectionScalesT) {
    const Sphere s{{0, 0, -10}, 2};
    const auto t = intersect(s, Ray{{0, 0, 0}, {0, 0, -2}});
    ASSERT_TRUE(t);
    EXPECT_FLOAT_EQ(*t, 4.0f);
}

TEST(Sphere, HugeWallSphereIsAccurate) {
    // The report's floor: radius 990 centred 1000 below; surface at y = -10.
    const Sphere floor{{0, -1000, 0}, 990};
    const Ray down = Ray{{0, 0, 0}, {0, -1, 0}};
    const auto t = intersect(floor, down);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 10.0f, 1e-4f);
    const glm::vec3 n = normal_at(floor, down.at(*t));
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);
}

TEST(Sphere, ZeroOrNanDirectionMisses) {
    const Sphere s{{0, 0, 0}, 1};
    EXPECT_FALSE(intersect(s, Ray{{0, 0, 5}, {0, 0, 0}}));
    EXPECT_FALSE(intersect(s, Ray{{0, 0, 5}, {NAN, 0, -1}}));
}
