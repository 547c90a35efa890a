// Light choice by power times a bound of each light's contribution (issue 15 item 3):
// the per-point pmf sums to 1, gives 0 only to lights whose own samples bring nothing to
// the point, is what the sampler draws, and the MIS path tracer using it (its BSDF-hit
// weights taking the same per-point pmf) equals the brute-force tracer.

#include "light_scene_test_util.h"

#include <librt/render/integrators.h>
#include <librt/render/light_bounds.h>
#include <librt/render/light_sampler.h>
#include <librt/render/scene.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

namespace librt {
namespace {

using testing::add_floor_and_ball;
using testing::Pinhole;
using testing::region;
using testing::render_stats;

Light light_of(LightSource source, bool one_sided = false) {
    Light l;
    l.source = std::move(source);
    l.one_sided = one_sided;
    return l;
}

/// One light of every kind, placed so that the test's points see some from below, behind
/// or outside their cones.
std::vector<Light> every_kind() {
    std::vector<Light> lights;
    lights.push_back(light_of(PointLight{{0.5f, 2.0f, 0.0f}, glm::vec3(3.0f)}));
    lights.push_back(light_of(SphereLight{Sphere{{-1.0f, 1.5f, 1.0f}, 0.3f}, glm::vec3(5.0f)}));
    QuadLight down{{-0.5f, 2.5f, -0.5f},
                   {1.0f, 0.0f, 0.0f},
                   {0.0f, 0.0f, 1.0f},
                   glm::vec3(4.0f),
                   false};  // edge0 x edge1 = -y: faces down
    lights.push_back(light_of(down, true));
    QuadLight wall{{2.0f, 0.0f, -1.0f},
                   {0.0f, 1.0f, 0.0f},
                   {0.0f, 0.0f, 2.0f},
                   glm::vec3(2.0f),
                   true};  // two-sided, vertical
    lights.push_back(light_of(wall));
    DiskLight up{{0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.4f, glm::vec3(6.0f), false};
    lights.push_back(light_of(up, true));
    SpotLight spot;
    spot.position = {-1.5f, 2.0f, -1.5f};
    spot.direction = {0.3f, -1.0f, 0.3f};
    spot.intensity = glm::vec3(8.0f);
    spot.inner_angle = 0.2f;
    spot.outer_angle = 0.5f;
    lights.push_back(light_of(spot));
    TriangleLight tri;
    tri.p0 = {1.0f, 0.5f, 1.5f};
    tri.p1 = {1.5f, 0.5f, 1.5f};
    tri.p2 = {1.0f, 1.2f, 1.8f};
    tri.radiance = glm::vec3(7.0f);
    lights.push_back(light_of(tri));
    DirectionalLight sun{{0.2f, 1.0f, 0.1f}, glm::vec3(1.5f), 0.05f, 10.0f};
    lights.push_back(light_of(sun));
    EnvironmentLight sky = EnvironmentLight::constant(glm::vec3(0.2f));
    sky.scene_radius = 10.0f;
    lights.push_back(light_of(sky));
    return lights;
}

/// True when any of `count` samples of the light's own sample_li brings light to `at`:
/// valid, non-zero radiance, and above the surface's plane for a reflecting BSDF.
bool any_sample_arrives(const Light& light, const LightChoicePoint& at, Pcg32& rng, int count) {
    for (int i = 0; i < count; ++i) {
        const LightLiSample s = sample_li(light, at.point, {rng.next_float(), rng.next_float()});
        if (!s.valid() || !(std::max({s.radiance.x, s.radiance.y, s.radiance.z}) > 0.0f)) continue;
        if (at.reflect_only && !(glm::dot(s.wi, at.normal) > 0.0f)) continue;
        return true;
    }
    return false;
}

glm::vec3 random_unit(Pcg32& rng) {
    const float z = 2.0f * rng.next_float() - 1.0f;
    const float phi = 2.0f * 3.14159265f * rng.next_float();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

TEST(BoundedLightChoice, PmfSumsToOneAndIsZeroOnlyForLightsThatBringNothing) {
    const std::vector<Light> lights = every_kind();
    const LightSampler sampler(lights);
    ASSERT_LE(lights.size(), LightSampler::k_max_bounded);
    Pcg32 rng(2024, 3);
    int ruled_out = 0, pairs = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        LightChoicePoint at;
        at.point = {4.0f * rng.next_float() - 2.0f, 4.0f * rng.next_float() - 1.5f,
                    4.0f * rng.next_float() - 2.0f};
        at.normal = random_unit(rng);
        at.reflect_only = rng.next_float() < 0.8f;
        double sum = 0.0;
        for (std::uint32_t i = 0; i < lights.size(); ++i) {
            const float p = sampler.pmf(i, at);
            ASSERT_GE(p, 0.0f);
            sum += p;
            ++pairs;
            // Conservative: a light some of whose samples arrive is never ruled out.
            if (p == 0.0f) {
                ++ruled_out;
                EXPECT_FALSE(any_sample_arrives(lights[i], at, rng, 256))
                    << "light " << i << " ruled out at (" << at.point.x << ", " << at.point.y
                    << ", " << at.point.z << ") but its samples arrive";
            }
        }
        // The environment always arrives, so something is always chosen.
        EXPECT_NEAR(sum, 1.0, 1e-5) << "trial " << trial;
        // sample() returns the light and the pmf that pmf() reports.
        const SampledLight s = sampler.sample(rng.next_float(), at);
        ASSERT_TRUE(s.valid());
        EXPECT_EQ(s.pmf, sampler.pmf(s.light, at));
    }
    // The bound says something: lights are ruled out at a good share of the points.
    EXPECT_GT(ruled_out, pairs / 10) << ruled_out << " of " << pairs;
}

TEST(BoundedLightChoice, SampleFrequenciesMatchThePmf) {
    const std::vector<Light> lights = every_kind();
    const LightSampler sampler(lights);
    LightChoicePoint at{{0.2f, 0.0f, 0.3f}, {0.0f, 1.0f, 0.0f}, true};
    const int n = 200000;
    std::vector<int> count(lights.size(), 0);
    Pcg32 rng(7, 1);
    for (int i = 0; i < n; ++i) {
        const SampledLight s = sampler.sample(rng.next_float(), at);
        ASSERT_TRUE(s.valid());
        ++count[s.light];
    }
    for (std::uint32_t i = 0; i < lights.size(); ++i) {
        const double p = sampler.pmf(i, at);
        // Binomial count: within 5 standard deviations (+1 for p = 0 exactly).
        const double sd = std::sqrt(n * p * (1.0 - p));
        EXPECT_LE(std::fabs(count[i] - n * p), 5.0 * sd + 1.0) << "light " << i << " pmf " << p;
    }
    // The disk at y = -1 lies wholly below the plane of this floor point: ruled out.
    EXPECT_EQ(sampler.pmf(4, at), 0.0f);
    // A near light gets more than its power share: the bound favours it.
    EXPECT_GT(sampler.pmf(0, at), 0.0f);
}

TEST(BoundedLightChoice, PointAboveOneSidedQuadAndOutsideSpotConeGetsNothingFromThem) {
    const std::vector<Light> lights = every_kind();
    const LightSampler sampler(lights);
    // Above the downward quad (y = 2.5), facing up: the quad emits down, the point is
    // behind it; even a transmissive surface receives nothing.
    const LightChoicePoint above{{0.0f, 3.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, false};
    EXPECT_EQ(sampler.pmf(2, above), 0.0f);
    EXPECT_GT(sampler.pmf(3, above), 0.0f);  // the two-sided wall still counts
    // The spot points down and a little toward +x +z from (-1.5, 2, -1.5): a point far to
    // the other side lies outside its cone.
    const LightChoicePoint outside{{-3.0f, 0.0f, 2.0f}, {0.0f, 1.0f, 0.0f}, true};
    EXPECT_EQ(sampler.pmf(5, outside), 0.0f);
}

/// Renders the scene with the MIS tracer choosing lights by bounds, and by power, and with
/// the brute-force tracer; all three must agree.
void expect_bounded_mis_equals_brute(const Scene& scene, int spp_mis, int spp_brute,
                                     const char* what) {
    PathTracerSettings s;
    s.max_depth = 3;
    s.russian_roulette = false;
    s.light_choice = LightChoice::Bounded;
    PathTracer bounded(s);
    s.light_choice = LightChoice::Power;
    PathTracer by_power(s);
    BruteForcePathTracer brute(s);
    const Pinhole cam = testing::side_camera();
    const auto a = render_stats(scene, bounded, cam, spp_mis, 21);
    const auto b = render_stats(scene, brute, cam, spp_brute, 22);
    const auto c = render_stats(scene, by_power, cam, spp_mis, 23);
    const auto whole = region(a, 0, 0, a.width, a.height);
    EXPECT_GT(whole.mean.x + whole.mean.y + whole.mean.z, 1e-3) << what << ": black image";
    const std::string name = what;
    testing::expect_images_agree(a, b, name + ": bounded vs brute force");
    testing::expect_images_agree(a, c, name + ": bounded vs power");
}

TEST(BoundedLightChoice, MisWithPerPointPmfEqualsBruteForce) {
    Scene scene;
    add_floor_and_ball(scene);
    // A bright far sphere light that takes most of the power table, and a dim wide panel
    // just above the ball facing down that the bound favours near it: there the per-point
    // pmf and the power table's differ most, so a BSDF hit weighed with the wrong one
    // would show. Also a disk under the floor facing up (ruled out above the floor) and a
    // side panel at x = 1.2 facing away from the ball (+x: ruled out left of it).
    (void)scene.add_sphere_light(SphereLight{Sphere{{-4.0f, 6.0f, 3.0f}, 0.6f}, glm::vec3(60.0f)});
    (void)scene.add_quad_light(QuadLight{{-0.9f, 1.2f, -0.9f},
                                         {1.8f, 0.0f, 0.0f},
                                         {0.0f, 0.0f, 1.8f},
                                         glm::vec3(2.5f, 2.2f, 2.0f),
                                         false});
    (void)scene.add_disk_light(
        DiskLight{{0.0f, -0.5f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.5f, glm::vec3(8.0f), false});
    (void)scene.add_quad_light(QuadLight{
        {1.2f, 0.2f, -1.0f}, {0.0f, 0.8f, 0.0f}, {0.0f, 0.0f, 0.8f}, glm::vec3(3.0f), false});
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 4u);
    // The power table gives the panel little; the bound, under it, much more.
    const LightChoicePoint under{{0.0f, 0.0f, -1.2f}, {0.0f, 1.0f, 0.0f}, true};
    EXPECT_LT(scene.light_sampler().pmf(1), 0.05f);
    EXPECT_GT(scene.light_sampler().pmf(1, under), 0.25f);
    expect_bounded_mis_equals_brute(scene, 128, 1024, "four area lights");
}

TEST(BoundedLightChoice, MoreLightsThanTheBoundedLimitFallBackToPowerAndStayUnbiased) {
    Scene scene;
    add_floor_and_ball(scene);
    // A ring of 24 small emissive triangles facing down over the floor, and 4 under it.
    TriangleMesh ring;
    for (int i = 0; i < 28; ++i) {
        const float a = 2.0f * 3.14159265f * float(i) / 28.0f;
        const float y = i < 24 ? 2.0f : -0.3f;
        const glm::vec3 c{1.2f * std::cos(a), y, 1.2f * std::sin(a)};
        const auto base = std::uint32_t(ring.positions.size());
        ring.positions.push_back(c + glm::vec3(-0.15f, 0.0f, -0.15f));
        ring.positions.push_back(c + glm::vec3(0.15f, 0.0f, -0.15f));
        ring.positions.push_back(c + glm::vec3(0.0f, 0.0f, 0.2f));
        ring.triangles.push_back({base, base + 1, base + 2});
    }
    scene.add_mesh(ring, scene.add_material(Material::emissive(glm::vec3(6.0f, 5.0f, 4.0f))));
    scene.commit();
    ASSERT_GT(scene.lights().size(), LightSampler::k_max_bounded);
    expect_bounded_mis_equals_brute(scene, 64, 512, "28 emissive triangles");
}

}  // namespace
}  // namespace librt
