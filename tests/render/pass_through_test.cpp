// A smooth thin-walled transmissive surface (the glTF material at roughness 0 with
// KHR_materials_transmission) is a Null lobe: light passes it undeviated with the colour
// (1 - metallic) (1 - Fr(cos_o)) transmission c, the integrators cross it without a bounce,
// and shadow rays see lights through it. Checked against the closed form of that colour,
// the energy balance of the two parts (reflection + pass-through = 1 for a white,
// non-absorbing pane), and a floor lit through a pane against quadrature over the light.

#include <librt/integrator/integrators.h>
#include <librt/light/quad_light.h>
#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace librt {
namespace {

ShadingPoint flat_point() {
    ShadingPoint p;
    p.frame = ShadingFrame::at({0, 0, 1}, {0, 0, 1}, {0, 0, -1});
    p.albedo = glm::vec3(1.0f);
    return p;
}

glm::vec3 direction_at(float theta) { return {std::sin(theta), 0.0f, std::cos(theta)}; }

// Schlick's Fresnel with F0 = 0.04 (ior 1.5), as the glTF specification's Appendix B writes it.
float schlick(float cos_theta) { return 0.04f + 0.96f * std::pow(1.0f - cos_theta, 5.0f); }

TEST(PassThrough, SmoothTransmissionIsANullLobeOfTheClosedFormColour) {
    const glm::vec3 c(0.9f, 0.8f, 0.7f);
    const Material glass = Material::metallic_roughness(c, 0.25f, 0.0f, 1.5f, 0.6f);
    EXPECT_TRUE(has(lobes(glass), BsdfLobe::Null));
    EXPECT_FALSE(has(lobes(glass), BsdfLobe::Transmission));
    EXPECT_TRUE(may_pass_through(glass));
    const ShadingPoint p = flat_point();
    for (const float theta : {0.0f, 0.5f, 1.0f, 1.4f}) {
        const glm::vec3 wo = direction_at(theta);
        const glm::vec3 expected = (1.0f - 0.25f) * (1.0f - schlick(wo.z)) * 0.6f * c;
        const glm::vec3 t = pass_through(glass, p, wo);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(t[i], expected[i], 1e-6f) << theta;
        // The delta is not part of f or its density.
        EXPECT_EQ(eval(glass, p, wo, -wo), glm::vec3(0.0f));
        EXPECT_EQ(pdf(glass, p, wo, -wo), 0.0f);
    }
}

TEST(PassThrough, RoughMetallicOrAnisotropicTransmissionKeepsItsGlossyLobe) {
    const glm::vec3 wo = direction_at(0.3f);
    const ShadingPoint p = flat_point();
    const Material rough = Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.5f, 1.5f, 1.0f);
    EXPECT_TRUE(has(lobes(rough), BsdfLobe::Transmission));
    EXPECT_FALSE(has(lobes(rough), BsdfLobe::Null));
    EXPECT_EQ(pass_through(rough, p, wo), glm::vec3(0.0f));
    EXPECT_TRUE(may_pass_through(rough));  // a roughness texture may make a point smooth
    Material metal = Material::metallic_roughness(glm::vec3(1.0f), 1.0f, 0.0f, 1.5f, 1.0f);
    EXPECT_FALSE(has(lobes(metal), BsdfLobe::Null));
    Material aniso = Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.0f, 1.5f, 1.0f);
    aniso.anisotropy = 0.5f;  // KHR_materials_anisotropy widens the tangent's alpha
    EXPECT_FALSE(has(lobes(aniso), BsdfLobe::Null));
    const Material opaque = Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.0f);
    EXPECT_FALSE(may_pass_through(opaque));
    EXPECT_FALSE(may_pass_through(Material::diffuse(glm::vec3(0.5f))));
}

// A white pane that transmits everything it does not reflect (transmission 1, metallic 0)
// loses nothing: the albedo of what sample() draws (the specular reflection, alpha 10^-3)
// plus pass_through(wo) is 1 at every angle, up to GGX's tiny energy loss and noise.
TEST(PassThrough, ReflectionAndPassThroughSumToOne) {
    const Material pane = Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.0f, 1.5f, 1.0f);
    const ShadingPoint p = flat_point();
    Pcg32 rng(7, 3);
    for (const float theta : {0.1f, 0.7f, 1.2f, 1.5f}) {
        const glm::vec3 wo = direction_at(theta);
        constexpr int n = 20000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            const float uc = rng.next_float();
            const glm::vec2 u(rng.next_float(), rng.next_float());
            const BsdfSample s = sample(pane, p, wo, uc, u);
            ASSERT_FALSE(s.valid() && has(s.lobe, BsdfLobe::Transmission)) << theta;
            const double w = s.valid() ? double(s.weight.y) : 0.0;
            sum += w;
            sum2 += w * w;
        }
        const double mean = sum / n;
        const double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
        const double total = mean + double(pass_through(pane, p, wo).y);
        // 5 standard errors plus 0.5 % for GGX's single-scattering loss at alpha 10^-3.
        EXPECT_NEAR(total, 1.0, 5.0 * se + 0.005) << "theta " << theta;
    }
}

constexpr float kRadiance = 8.0f;
constexpr float kFloorAlbedo = 0.5f;
constexpr float kPaneY = 1.0f;
constexpr float kLightY = 2.0f;

// A white floor at y = 0, a 40 x 40 smooth pane (transmission 1) at y = 1 and a one-sided
// 1 x 1 quad light at y = 2 facing down: every light path to the floor crosses the pane.
void build_pane_room(Scene& scene) {
    TriangleMesh floor;
    floor.positions = {{-20, 0, -20}, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(floor, scene.add_material(Material::diffuse(glm::vec3(kFloorAlbedo))));
    TriangleMesh pane = floor;
    for (glm::vec3& v : pane.positions) v.y = kPaneY;
    scene.add_mesh(pane, scene.add_material(Material::metallic_roughness(glm::vec3(1.0f), 0.0f,
                                                                         0.0f, 1.5f, 1.0f)));
    (void)scene.add_quad_light(QuadLight{{-0.5f, kLightY, -0.5f},
                                         {1.0f, 0, 0},
                                         {0, 0, 1.0f},
                                         glm::vec3(kRadiance),
                                         false});  // edge0 x edge1 = -y: faces the floor
    scene.commit();
}

// The floor point x's radiance at depth 1: (albedo / pi) L integral over the light of
// T(theta) cos_floor cos_light / d^2 dA, T = 1 - Fr(cos) the pane's pass-through along the
// segment (the pane is horizontal, so its cosine is the floor's). Midpoint rule, 400^2 cells.
double floor_radiance_by_quadrature(const glm::dvec3& x) {
    constexpr int k = 400;
    double sum = 0.0;
    for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) {
            const glm::dvec3 y(-0.5 + (i + 0.5) / k, kLightY, -0.5 + (j + 0.5) / k);
            const glm::dvec3 d = y - x;
            const double d2 = glm::dot(d, d);
            const double cos_t = d.y / std::sqrt(d2);  // floor's and light's cosine alike
            const double t = 1.0 - (0.04 + 0.96 * std::pow(1.0 - cos_t, 5.0));
            sum += t * cos_t * cos_t / d2;
        }
    }
    return kFloorAlbedo / M_PI * kRadiance * sum / (double(k) * k);
}

struct Estimate {
    double mean = 0.0, se = 0.0;
};

// n samples of the radiance along the ray from just under the pane to floor point x.
Estimate estimate(const Scene& scene, const Integrator& integrator, const glm::vec3& x, int n,
                  std::uint64_t seed) {
    Ray ray;
    ray.origin = x + glm::vec3(0.2f, 0.5f, -0.1f);
    ray.direction = glm::normalize(x - ray.origin);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        Sampler sampler(SamplerKind::Independent, 0, 0, std::uint32_t(i), seed);
        const double v = double(integrator.li(scene, ray, sampler).y);
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1))};
}

// At max depth 1, the radiance of floor point (0.3, 0, -0.2) by direct lighting, the MIS
// path tracer and brute force each equals floor_radiance_by_quadrature, within 5 standard
// errors plus 0.1 % for the quadrature.
void expect_direct_light_matches_quadrature(const Scene& scene) {
    PathTracerSettings settings;
    settings.max_depth = 1;
    settings.russian_roulette = false;
    const glm::vec3 x(0.3f, 0.0f, -0.2f);
    const double expected = floor_radiance_by_quadrature(glm::dvec3(x));
    ASSERT_GT(expected, 0.1);
    constexpr int n = 20000;
    const Estimate direct = estimate(scene, DirectLighting(DirectLightingSettings{1}), x, n, 3);
    const Estimate mis = estimate(scene, PathTracer(settings), x, n, 4);
    const Estimate brute = estimate(scene, BruteForcePathTracer(settings), x, 4 * n, 5);
    EXPECT_NEAR(direct.mean, expected, 5.0 * direct.se + 1e-3 * expected);
    EXPECT_NEAR(mis.mean, expected, 5.0 * mis.se + 1e-3 * expected);
    EXPECT_NEAR(brute.mean, expected, 5.0 * brute.se + 1e-3 * expected);
}

// At max depth 1 the floor is the path's one scattering event: what reaches it through
// the pane must count there (a crossing is no bounce). Before the Null lobe, the pane was
// a glossy occluder and this read 0.
TEST(PassThrough, FloorLitThroughAPaneMatchesQuadrature) {
    Scene scene;
    build_pane_room(scene);
    ASSERT_TRUE(scene.has_pass_through_surfaces());
    expect_direct_light_matches_quadrature(scene);
}

// A pane lying on the floor, in its plane (a glass box resting on it): rays meet the pane
// and the floor at the same t but for rounding, and crossing the pane restarts the ray past
// that plane, so the floor was lost whenever the pane came first (about half the rays).
// The surface under a pane is taken instead of the pane: the floor reads what it reads
// with no pane there, for each estimator. (Under two coplanar panes it can still be lost:
// only one object is left out of the search; Scene::surface_under_pane.)
TEST(PassThrough, APaneLyingOnTheFloorHidesNothing) {
    Scene scene;
    TriangleMesh floor;
    floor.positions = {{-20, 0, -20}, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(floor, scene.add_material(Material::metallic_roughness(glm::vec3(1.0f), 0.0f,
                                                                          0.0f, 1.5f, 1.0f)));
    build_pane_room(scene);  // its own floor, in the same plane, and the pane above
    expect_direct_light_matches_quadrature(scene);
}

// Longer paths: the pane also reflects (its specular lobe) and the floor's light bounces
// between them; the MIS path tracer, whose light samples cross the pane, agrees with brute
// force, whose paths cross it only by chance. Both with the Sobol' sampler too, whose
// crossing decisions take dimensions of their own.
TEST(PassThrough, MisAgreesWithBruteForceOnLongerPaths) {
    Scene scene;
    build_pane_room(scene);
    PathTracerSettings settings;
    settings.max_depth = 4;
    settings.russian_roulette = false;
    const glm::vec3 x(-0.4f, 0.0f, 0.6f);
    constexpr int n = 40000;
    const Estimate mis = estimate(scene, PathTracer(settings), x, n, 11);
    const Estimate brute = estimate(scene, BruteForcePathTracer(settings), x, 4 * n, 12);
    EXPECT_GT(mis.mean, floor_radiance_by_quadrature(glm::dvec3(x)));  // more than direct
    EXPECT_NEAR(mis.mean, brute.mean, 5.0 * std::sqrt(mis.se * mis.se + brute.se * brute.se));

    double sum = 0.0, sum2 = 0.0;
    Ray ray;
    ray.origin = x + glm::vec3(0.2f, 0.5f, -0.1f);
    ray.direction = glm::normalize(x - ray.origin);
    const PathTracer tracer(settings);
    for (int i = 0; i < n; ++i) {
        Sampler sampler(SamplerKind::Sobol, 3, 5, std::uint32_t(i), 21);
        const double v = double(tracer.li(scene, ray, sampler).y);
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n;
    const double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, brute.mean, 5.0 * std::sqrt(se * se + brute.se * brute.se));
}

}  // namespace
}  // namespace librt
