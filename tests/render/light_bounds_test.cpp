// Light choice by power times a bound of each light's contribution (issue 15 item 3):
// the per-point pmf sums to 1, gives 0 only to lights whose own samples bring nothing to
// the point, is what the sampler draws, and the MIS path tracer using it (its BSDF-hit
// weights taking the same per-point pmf) equals the brute-force tracer.

#include "light/light_bounds.h"

#include "light_scene_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/light/light_sampler.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <type_traits>
#include <variant>
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

/// Every light's pmf at `at`: each >= 0, and 0 only for a light none of whose `samples`
/// own samples arrives (counted in ruled_out); returns their sum.
double check_pmfs(const LightSampler& sampler, const std::vector<Light>& lights,
                  const LightChoicePoint& at, Pcg32& rng, int samples, int& ruled_out) {
    double sum = 0.0;
    for (std::uint32_t i = 0; i < lights.size(); ++i) {
        const float p = sampler.pmf(i, at);
        EXPECT_GE(p, 0.0f);
        sum += p;
        // Conservative: a light some of whose samples arrive is never ruled out.
        if (p == 0.0f) {
            ++ruled_out;
            EXPECT_FALSE(any_sample_arrives(lights[i], at, rng, samples))
                << "light " << i << " ruled out at (" << at.point.x << ", " << at.point.y << ", "
                << at.point.z << ") but its samples arrive";
        }
    }
    return sum;
}

TEST(BoundedLightChoice, PmfSumsToOneAndIsZeroOnlyForLightsThatBringNothing) {
    const std::vector<Light> lights = every_kind();
    const LightSampler sampler(lights);
    ASSERT_LE(lights.size(), LightSampler::kMaxBounded);
    Pcg32 rng(2024, 3);
    int ruled_out = 0, pairs = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        LightChoicePoint at;
        at.point = {4.0f * rng.next_float() - 2.0f, 4.0f * rng.next_float() - 1.5f,
                    4.0f * rng.next_float() - 2.0f};
        at.normal = random_unit(rng);
        at.reflect_only = rng.next_float() < 0.8f;
        const double sum = check_pmfs(sampler, lights, at, rng, 256, ruled_out);
        pairs += int(lights.size());
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

TEST(BoundedLightChoice, MoreLightsThanTheBoundedLimitUseTheLightTreeAndStayUnbiased) {
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
    ASSERT_GT(scene.lights().size(), LightSampler::kMaxBounded);
    // The tree is in use: under one triangle of the ring, that triangle gets more than its
    // power share (1/28), and the four under the floor nothing (the power table gives them
    // 4/28).
    const LightSampler& ls = scene.light_sampler();
    const LightChoicePoint under{{1.2f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, true};
    std::uint32_t nearest = 0;
    for (std::uint32_t i = 0; i < ls.size(); ++i) {
        if (glm::length(ls.bounds(i).centre - glm::vec3(1.2f, 2.0f, 0.0f)) <
            glm::length(ls.bounds(nearest).centre - glm::vec3(1.2f, 2.0f, 0.0f))) {
            nearest = i;
        }
        if (ls.bounds(i).centre.y < 0.0f) {
            EXPECT_EQ(ls.pmf(i, under), 0.0f) << "light " << i;
        }
    }
    EXPECT_GT(ls.pmf(nearest, under), ls.pmf(nearest));
    expect_bounded_mis_equals_brute(scene, 64, 512, "28 emissive triangles");
}

/// Whether two renders gave the same sums in every pixel (the same samples, bit for bit).
bool same_sums(const testing::StatImage& a, const testing::StatImage& b) {
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        if (a.pixels[i].sum != b.pixels[i].sum) return false;
    return a.pixels.size() == b.pixels.size();
}

// LightChoice::Auto, the default, is the bounded choice (the light tree) above kMaxBounded
// lights and the power table up to it: its image is the one or the other's bit for bit,
// and on many lights the two differ (so the comparison tells them apart).
TEST(BoundedLightChoice, AutoIsBoundedAboveTheLimitAndPowerUpToIt) {
    const auto renders = [](const Scene& scene) {
        PathTracerSettings s;
        s.max_depth = 3;
        std::vector<testing::StatImage> images;
        for (const LightChoice choice :
             {LightChoice::Auto, LightChoice::Bounded, LightChoice::Power}) {
            s.light_choice = choice;
            PathTracer tracer(s);
            images.push_back(render_stats(scene, tracer, testing::side_camera(), 4, 5));
        }
        return images;
    };
    for (const int lights : {4, 28}) {
        Scene scene;
        add_floor_and_ball(scene);
        TriangleMesh ring;
        for (int i = 0; i < lights; ++i) {
            const float a = 2.0f * 3.14159265f * float(i) / float(lights);
            const glm::vec3 c{1.2f * std::cos(a), 2.0f, 1.2f * std::sin(a)};
            const auto base = std::uint32_t(ring.positions.size());
            ring.positions.push_back(c + glm::vec3(-0.15f, 0.0f, -0.15f));
            ring.positions.push_back(c + glm::vec3(0.15f, 0.0f, -0.15f));
            ring.positions.push_back(c + glm::vec3(0.0f, 0.0f, 0.2f));
            ring.triangles.push_back({base, base + 1, base + 2});
        }
        scene.add_mesh(ring, scene.add_material(Material::emissive(glm::vec3(6.0f))));
        scene.commit();
        ASSERT_EQ(scene.lights().size(), std::size_t(lights));
        const std::vector<testing::StatImage> images = renders(scene);
        const bool many = scene.lights().size() > LightSampler::kMaxBounded;
        EXPECT_TRUE(same_sums(images[0], images[many ? 1 : 2])) << lights << " lights";
        if (many) EXPECT_FALSE(same_sums(images[1], images[2])) << lights << " lights";
    }
}

TEST(BoundedLightChoice, LightTreeOverAreaLightsOfEveryKindEqualsBruteForce) {
    // 24 area lights (the brute-force tracer can only see emitters it hits): a bright far
    // sphere light that takes most of the power table, then one-sided quads and disks
    // turned every way (some face away from everything), two-sided quads and small sphere
    // lights, around and above the ball, which the tree favours near them: a BSDF hit
    // weighed with the power table's pmf instead of the tree's fails this test. Beyond 16
    // lights: the tree.
    Scene scene;
    add_floor_and_ball(scene);
    (void)scene.add_sphere_light(SphereLight{Sphere{{-4.0f, 6.0f, 3.0f}, 0.6f}, glm::vec3(20.0f)});
    Pcg32 rng(31, 2);
    for (int i = 1; i < 24; ++i) {
        const glm::vec3 at{3.0f * rng.next_float() - 1.5f, 0.3f + 2.0f * rng.next_float(),
                           3.0f * rng.next_float() - 1.5f};
        const glm::vec3 n = random_unit(rng);
        const glm::vec3 t = glm::normalize(
            glm::cross(n, std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
        const glm::vec3 radiance =
            glm::vec3(0.5f + rng.next_float(), 0.5f + rng.next_float(), 0.5f + rng.next_float()) *
            (1.0f + 2.0f * rng.next_float());
        switch (i % 4) {
            case 0:  // one-sided quad facing n
                (void)scene.add_quad_light(
                    QuadLight{at, 0.6f * glm::cross(n, t), 0.6f * t, radiance, false});
                break;
            case 1:
                (void)scene.add_disk_light(DiskLight{at, n, 0.3f, radiance, false});
                break;
            case 2:  // two-sided
                (void)scene.add_quad_light(
                    QuadLight{at, 0.25f * glm::cross(n, t), 0.25f * t, radiance, true});
                break;
            default:
                (void)scene.add_sphere_light(SphereLight{Sphere{at, 0.08f}, radiance});
                break;
        }
    }
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 24u);
    expect_bounded_mis_equals_brute(scene, 64, 1024, "24 area lights of every kind");
}

/// `count` lights of every kind placed at random in a 10 x 4 x 10 box, turned at random,
/// with powers spread over two orders of magnitude; and one sun and one sky.
std::vector<Light> many_lights(int count, std::uint64_t seed) {
    const std::vector<Light> kinds = every_kind();
    std::vector<Light> lights;
    Pcg32 rng(seed, 5);
    for (int i = 0; i < count; ++i) {
        Light l = kinds[std::size_t(i) % 7];  // the seven finite kinds
        const glm::vec3 at{10.0f * rng.next_float() - 5.0f, 4.0f * rng.next_float() - 1.0f,
                           10.0f * rng.next_float() - 5.0f};
        const glm::vec3 dir = random_unit(rng);
        const float scale = std::pow(10.0f, 2.0f * rng.next_float() - 1.0f);
        std::visit(
            [&](auto& src) {
                using T = std::decay_t<decltype(src)>;
                if constexpr (std::is_same_v<T, PointLight>) {
                    src.position = at;
                    src.intensity *= scale;
                } else if constexpr (std::is_same_v<T, SphereLight>) {
                    src.sphere.center = at;
                    src.radiance *= scale;
                } else if constexpr (std::is_same_v<T, QuadLight>) {
                    src.corner = at;
                    src.radiance *= scale;
                    // Edges turned so that the normal is `dir`.
                    const glm::vec3 t = glm::normalize(glm::cross(
                        dir, std::fabs(dir.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
                    src.edge0 = 0.5f * t;
                    src.edge1 = 0.4f * glm::cross(dir, t);
                } else if constexpr (std::is_same_v<T, DiskLight>) {
                    src.center = at;
                    src.normal = dir;
                    src.radiance *= scale;
                } else if constexpr (std::is_same_v<T, SpotLight>) {
                    src.position = at;
                    src.direction = dir;
                    src.intensity *= scale;
                } else if constexpr (std::is_same_v<T, TriangleLight>) {
                    const glm::vec3 shift = at - src.p0;
                    src.p0 += shift;
                    src.p1 += shift;
                    src.p2 += shift;
                    src.radiance *= scale;
                }
            },
            l.source);
        lights.push_back(l);
    }
    lights.push_back(kinds[7]);  // the sun
    lights.push_back(kinds[8]);  // the sky
    return lights;
}

LightChoicePoint random_point(Pcg32& rng) {
    LightChoicePoint at;
    at.point = {12.0f * rng.next_float() - 6.0f, 5.0f * rng.next_float() - 1.5f,
                12.0f * rng.next_float() - 6.0f};
    at.normal = random_unit(rng);
    at.reflect_only = rng.next_float() < 0.8f;
    return at;
}

TEST(LightTree, PmfIsWhatSampleDrawsAndZeroOnlyForLightsThatBringNothing) {
    const std::vector<Light> lights = many_lights(300, 11);
    const LightSampler sampler(lights);
    ASSERT_GT(lights.size(), LightSampler::kMaxBounded);
    Pcg32 rng(99, 4);
    int ruled_out = 0, pairs = 0;
    for (int trial = 0; trial < 150; ++trial) {
        const LightChoicePoint at = random_point(rng);
        const double sum = check_pmfs(sampler, lights, at, rng, 64, ruled_out);
        pairs += int(lights.size());
        // A walk may end at a node whose children are both bounded by 0 (the node's bound
        // is looser than theirs): then nothing is chosen, and the pmfs sum to less than 1.
        EXPECT_LE(sum, 1.0 + 1e-5) << "trial " << trial;
        EXPECT_GT(sum, 0.0) << "trial " << trial;  // the sky always arrives
        for (int k = 0; k < 20; ++k) {
            const SampledLight s = sampler.sample(rng.next_float(), at);
            if (!s.valid()) continue;
            EXPECT_EQ(s.pmf, sampler.pmf(s.light, at)) << "light " << s.light;
        }
    }
    EXPECT_GT(ruled_out, pairs / 10) << ruled_out << " of " << pairs;
}

TEST(LightTree, SampleFrequenciesMatchThePmfAndFavourNearLights) {
    const std::vector<Light> lights = many_lights(300, 12);
    const LightSampler sampler(lights);
    Pcg32 rng(5, 9);
    for (int point = 0; point < 3; ++point) {
        const LightChoicePoint at = random_point(rng);
        const int n = 200000;
        std::vector<int> count(lights.size(), 0);
        int none = 0;
        for (int i = 0; i < n; ++i) {
            const SampledLight s = sampler.sample(rng.next_float(), at);
            if (s.valid()) {
                ++count[s.light];
            } else {
                ++none;
            }
        }
        double sum = 0.0;
        for (std::uint32_t i = 0; i < lights.size(); ++i) {
            const double p = sampler.pmf(i, at);
            sum += p;
            // Binomial count: within 5 standard deviations (+1 for p = 0 exactly).
            const double sd = std::sqrt(n * p * (1.0 - p));
            EXPECT_LE(std::fabs(count[i] - n * p), 5.0 * sd + 1.0)
                << "point " << point << " light " << i << " pmf " << p;
        }
        const double q = 1.0 - sum;  // the walks that choose nothing
        EXPECT_LE(std::fabs(none - n * q), 5.0 * std::sqrt(n * std::max(q, 0.0) * (1.0 - q)) + 1.0);
    }
    // Beside a light, the tree gives it far more than its power share.
    std::uint32_t point_light = 0;  // every seventh light is a point light
    const LightChoicePoint beside{
        std::get<PointLight>(lights[point_light].source).position + glm::vec3(0.05f, 0.0f, 0.0f),
        {-1.0f, 0.0f, 0.0f},
        true};
    EXPECT_GT(sampler.pmf(point_light, beside), 5.0f * sampler.pmf(point_light));
}

TEST(LightTree, CoincidentLightsShareByPower) {
    // Forty point lights at one place: no split by position exists, the tree halves them by
    // count, and from afar each gets its power share.
    std::vector<Light> lights;
    for (int i = 0; i < 40; ++i)
        lights.push_back(light_of(PointLight{{1.0f, 2.0f, 3.0f}, glm::vec3(float(1 + i % 5))}));
    const LightSampler sampler(lights);
    const LightChoicePoint at{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, true};
    double sum = 0.0;
    for (std::uint32_t i = 0; i < lights.size(); ++i) {
        EXPECT_NEAR(sampler.pmf(i, at), sampler.pmf(i), 1e-6f) << "light " << i;
        sum += sampler.pmf(i, at);
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
}

}  // namespace
}  // namespace librt
