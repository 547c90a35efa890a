// The light seam: each light's sample_li agrees with its pdf_li and its power, the Light
// variant dispatches to them, the power light sampler chooses lights with the
// probabilities it reports, and shadow rays built by spawn_ray_to stop short of the target.

#include "sampling/chi_square.h"
#include "scene/shadow_ray.h"

#include <librt/light/light.h>
#include <librt/light/light_sampler.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

namespace librt {
namespace {

TEST(LightSeam, PointLightIsADeltaLightWithInverseSquareRadiance) {
    const PointLight p{{1, 2, 3}, {10, 20, 30}};
    const Light light{p, kInvalidId};
    const glm::vec3 ref(1, 2, 1);  // 2 below
    const LightLiSample s = sample_li(light, ref, {0.3f, 0.7f});
    ASSERT_TRUE(s.valid());
    EXPECT_TRUE(s.is_delta);
    EXPECT_EQ(s.pdf, 1.0f);
    EXPECT_NEAR(glm::length(s.wi - glm::vec3(0, 0, 1)), 0.0f, 1e-7f);
    EXPECT_FLOAT_EQ(s.distance, 2.0f);
    EXPECT_FLOAT_EQ(s.radiance.y, 20.0f / 4.0f);  // I / d^2
    EXPECT_EQ(pdf_li(light, ref, s.wi), 0.0f);    // no sampled direction hits a point
    EXPECT_FLOAT_EQ(power(light).z, 4.0f * kPi * 30.0f);
    // At the light itself there is no direction.
    EXPECT_FALSE(sample_li(light, p.position, {0.5f, 0.5f}).valid());
}

// Sphere light, from outside and from inside: pdf_li at the sampled direction is the
// sample's pdf, the direction meets the sphere at the returned distance, and the power
// inverts SphereLight::radiance_for_power.
TEST(LightSeam, SphereLightSampleMatchesPdfAndSurface) {
    const SphereLight sl{{{0, 5, 0}, 1.5f}, {2, 3, 4}};
    const Light light{sl, 7};
    Pcg32 rng(11, 2);
    for (const glm::vec3 ref :
         {glm::vec3(0.3f, 0, 0.2f), glm::vec3(40, -3, 9), glm::vec3(0, 5.5f, 0.1f)}) {
        for (int i = 0; i < 2000; ++i) {
            const LightLiSample s = sample_li(light, ref, rng.next_vec2());
            ASSERT_TRUE(s.valid());
            EXPECT_FALSE(s.is_delta);
            EXPECT_EQ(s.radiance, sl.radiance);
            const float p = pdf_li(light, ref, s.wi);
            ASSERT_NEAR(p, s.pdf, 2e-3f * s.pdf);
            const glm::vec3 on = ref + s.distance * s.wi;
            ASSERT_NEAR(glm::length(on - sl.sphere.center), sl.sphere.radius, 1e-3f);
        }
    }
    // A direction away from the sphere, seen from outside, is never sampled.
    EXPECT_EQ(pdf_li(light, {0, 0, 0}, {0, -1, 0}), 0.0f);
    const glm::vec3 expected_power = sl.radiance * (4.0f * kPi * kPi * 1.5f * 1.5f);
    EXPECT_NEAR(power(light).x, expected_power.x, 1e-5f * expected_power.x);
    const glm::vec3 back = SphereLight::radiance_for_power(power(light), 1.5f);
    EXPECT_NEAR(back.z, sl.radiance.z, 1e-5f);
}

TEST(LightSampler, ChoosesByPowerWithTheReportedPmf) {
    std::vector<Light> lights = {
        {PointLight{{0, 0, 0}, glm::vec3(1.0f)}, kInvalidId},           // power 4 pi
        {PointLight{{0, 0, 0}, glm::vec3(0.0f)}, kInvalidId},           // power 0: never
        {SphereLight{{{0, 0, 0}, 1.0f}, glm::vec3(1.0f)}, kInvalidId},  // power 4 pi^2
        {PointLight{{0, 0, 0}, {3, 0, 0}}, kInvalidId},                 // mean power 4 pi
    };
    const LightSampler sampler(lights);
    ASSERT_EQ(sampler.size(), 4u);
    ASSERT_TRUE(sampler.any());
    const double total = 4.0 * kPi + 4.0 * kPi * kPi + 4.0 * kPi;
    EXPECT_NEAR(sampler.pmf(0), 4.0 * kPi / total, 1e-6);
    EXPECT_EQ(sampler.pmf(1), 0.0f);
    EXPECT_NEAR(sampler.pmf(2), 4.0 * kPi * kPi / total, 1e-6);
    EXPECT_NEAR(sampler.pmf(3), 4.0 * kPi / total, 1e-6);
    EXPECT_EQ(sampler.pmf(4), 0.0f);
    // Frequencies of 100k choices against the pmf (chi-square), and every choice reports
    // the pmf of the light it chose.
    std::vector<double> observed(4, 0.0), expected(4, 0.0);
    Pcg32 rng(3, 4);
    const int n = 100'000;
    for (int i = 0; i < n; ++i) {
        const SampledLight c = sampler.sample(rng.next_float());
        ASSERT_TRUE(c.valid());
        ASSERT_EQ(c.pmf, sampler.pmf(c.light));
        observed[c.light] += 1.0;
    }
    for (std::uint32_t i = 0; i < 4; ++i) expected[i] = n * double(sampler.pmf(i));
    EXPECT_EQ(observed[1], 0.0);
    const auto r = testing::chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.summary();
    EXPECT_GE(r.p_value, 0.01) << r.summary();
    // u at the ends of [0, 1) chooses a light with power.
    EXPECT_EQ(sampler.sample(0.0f).light, 0u);
    EXPECT_EQ(sampler.sample(std::nextafter(1.0f, 0.0f)).light, 3u);
}

TEST(LightSampler, NoLightsOrNoPowerChoosesNothing) {
    EXPECT_FALSE(LightSampler().sample(0.5f).valid());
    EXPECT_FALSE(LightSampler().any());
    const std::vector<Light> dark = {{PointLight{{0, 0, 0}, glm::vec3(0.0f)}, kInvalidId}};
    const LightSampler sampler(dark);
    EXPECT_EQ(sampler.size(), 1u);
    EXPECT_FALSE(sampler.any());
    EXPECT_FALSE(sampler.sample(0.5f).valid());
}

TEST(LightSeam, SceneKeepsALightListAndSampler) {
    Scene scene;
    scene.add_point_light({{0, 9, 0}, glm::vec3(1.0f)});
    const auto object = scene.add_sphere_light({{{0, 5, 0}, 1.0f}, glm::vec3(2.0f)});
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 2u);
    EXPECT_EQ(scene.light_sampler().size(), 2u);
    EXPECT_EQ(scene.light_of_object(object), 1u);
    EXPECT_EQ(scene.lights()[1].object, object);
    EXPECT_NEAR(scene.light_sampler().pmf(0) + scene.light_sampler().pmf(1), 1.0f, 1e-6f);
}

// spawn_ray_to: starts off the surface on the target's side; toward a point it ends
// kShadowEpsilon short of the target, toward a light sample at the distance itself, less
// end_slope times the origin's offset; unoccluded sees a blocker in between and ignores the
// object it is told to.
TEST(ShadowRay, SpawnRayToAndUnoccluded) {
    const glm::vec3 p(1, 0, 0), n(0, 1, 0), target(1, 10, 0);
    const Ray r = spawn_ray_to(p, n, target);
    EXPECT_GT(r.origin.y, 0.0f);
    EXPECT_NEAR(glm::length(r.direction), 1.0f, 1e-6f);
    const glm::vec3 end = r.at(r.t_max);
    EXPECT_LT(end.y, target.y);
    EXPECT_NEAR(end.y, target.y - kShadowEpsilon * (target.y - r.origin.y), 1e-5f);
    const Ray r2 = spawn_ray_to(p, n, ray_offset_scale(p), glm::vec3(0, 1, 0), 10.0f, 0.0f);
    EXPECT_EQ(r2.origin, r.origin);
    EXPECT_EQ(r2.t_max, 10.0f);
    const Ray r3 = spawn_ray_to(p, n, 0.25f, glm::vec3(0, 1, 0), 10.0f, 4.0f);
    EXPECT_EQ(r3.origin, p + 0.25f * n);
    EXPECT_EQ(r3.t_max, 9.0f);
    // Shorter than the slope's share: an empty segment.
    EXPECT_EQ(spawn_ray_to(p, n, 0.25f, glm::vec3(0, 1, 0), 0.5f, 4.0f).t_max, 0.0f);
    // A target at the point itself: a segment no longer than the offset, never negative.
    EXPECT_LE(spawn_ray_to(p, n, p).t_max, 2.0f * ray_offset_scale(p));
    EXPECT_GE(spawn_ray_to(p, n, p).t_max, 0.0f);

    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const auto blocker = scene.add_sphere({{1, 5, 0}, 1.0f}, m);
    (void)scene.add_sphere({{1, 11, 0}, 1.0f}, m);  // around the target: beyond t_max
    scene.commit();
    EXPECT_FALSE(unoccluded(scene, p, n, target));
    EXPECT_TRUE(unoccluded(scene, p, n, target, blocker));
    EXPECT_TRUE(unoccluded(scene, p, n, {-5, 0.5f, 0}));  // beside the blocker
}

// A light sample's shadow ray reaches the emitting point itself: a wall that the light's
// surface pokes through, crossed within kShadowEpsilon of the ray's length before the
// sample, still hides it. (With the relative margin the sample counted as lit: points of
// smallpt's light sphere just above its ceiling lit the room, +0.5 %.)
TEST(ShadowRay, LightSampleBeyondAWallByLessThanTheMarginIsHidden) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    // A ceiling at y = 80 (the bottom of a radius-1e4 ball) and a sphere light poking
    // through it, so that the shadow ray's end lies inside the ceiling's ball.
    (void)scene.add_sphere(glm::dvec3(0.0, 80.0 + 1e4, 0.0), 1e4, m);
    const std::uint32_t light_object =
        scene.add_sphere_light(SphereLight{Sphere{{0.0f, 100.0f, 0.0f}, 20.001f}, glm::vec3(1)});
    scene.commit();
    const glm::vec3 p(0, 0, 0), n(0, 1, 0);
    // Straight up, the light's lowest point (y = 79.999) is below the ceiling: lit.
    EXPECT_TRUE(unoccluded(
        scene, spawn_ray_to(p, n, ray_offset_scale(p), glm::vec3(0, 1, 0), 79.999f, 0.0f),
        light_object));
    // The point of the light's surface at y = 80.004 (x^2 = 20.001^2 - 19.996^2), on the
    // side facing p, lies inside the ceiling's ball; the ray crosses the ceiling 0.004
    // before reaching it, within the old margin (1e-4 x 80 = 0.008): hidden.
    const glm::vec3 q(std::sqrt(20.001f * 20.001f - 19.996f * 19.996f), 80.004f, 0.0f);
    const glm::vec3 wi = glm::normalize(q - p);
    EXPECT_FALSE(unoccluded(scene,
                            spawn_ray_to(p, n, ray_offset_scale(p), wi, glm::length(q - p), 0.0f),
                            light_object));
}

}  // namespace
}  // namespace librt
