// Emission sampling, for paths that start at lights (sample_le / pdf_le): the rays of
// every light carry its power, pdf_le gives back the densities of every sampled ray, the
// sampled origins and directions follow those densities (chi-square), one-sided lights
// emit nothing behind, and degenerate lights give no ray and no NaN.

#include "render/bsdf_chi_square_util.h"
#include "sampling/direction_bins.h"

#include <librt/light/light.h>
#include <librt/material/texture.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace librt {
namespace {

using testing::DirectionBins;
using testing::expect_chi_square_passes;
using testing::expected_counts;

constexpr double kPi = std::numbers::pi;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// The sphere lights at infinity start their rays from, away from the origin.
const SceneSphere kScene{{0.5f, -1.0f, 2.0f}, 3.0f};

/// A light named for failure messages.
struct Named {
    std::string name;
    Light light;
};

Light light_of(LightSource source) { return Light{std::move(source), kInvalidId}; }

/// A two-sided, untextured triangle light.
TriangleLight triangle(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                       const glm::vec3& radiance) {
    TriangleLight t;
    t.p0 = p0;
    t.p1 = p1;
    t.p2 = p2;
    t.radiance = radiance;
    return t;
}

/// Every finite kind of light, one- and two-sided where that applies, tilted and coloured
/// so that no axis or channel is special.
std::vector<Named> finite_lights() {
    const TriangleLight tri = triangle({0, 0, 0}, {2, 0.5f, 0}, {0.3f, 1.5f, 1}, {1, 2, 3});
    TriangleLight tri1 = tri;
    tri1.two_sided = false;
    const QuadLight quad{{1, 2, 3}, {1.5f, 0.2f, -0.3f}, {0.1f, 0.4f, 1.2f}, {3, 2, 1}, false};
    QuadLight quad2 = quad;
    quad2.two_sided = true;
    const DiskLight disk{{-1, 0.5f, 2}, {0.3f, -1.0f, 0.2f}, 0.7f, {0.5f, 1.5f, 2.5f}, false};
    DiskLight disk2 = disk;
    disk2.two_sided = true;
    const SphereLight sphere{{{1, 2, 3}, 0.8f}, {2.0f, 1.0f, 0.5f}};
    const PointLight point{{1, 2, 3}, {10, 20, 30}};
    const SpotLight spot{{0, 2, 0}, {0.2f, -1.0f, 0.1f}, {10, 8, 6}, 0.3f, 0.6f};
    const SpotLight wide_spot{{0, 2, 0}, {1.0f, 1.0f, 0.0f}, {1, 2, 3}, 0.0f, 0.5f * kPi};
    return {{"two-sided triangle", light_of(tri)},
            {"one-sided triangle", light_of(tri1)},
            {"one-sided quad", light_of(quad)},
            {"two-sided quad", light_of(quad2)},
            {"one-sided disk", light_of(disk)},
            {"two-sided disk", light_of(disk2)},
            {"sphere", light_of(sphere)},
            {"point", light_of(point)},
            {"spot", light_of(spot)},
            {"spot, hemisphere cone", light_of(wide_spot)}};
}

/// A 16 x 8 environment image of random colours (some pixels much brighter), turned.
EnvironmentImage random_image(std::uint64_t seed) {
    Pcg32 rng(seed, 5);
    EnvironmentImage im{16, 8, {}};
    for (int i = 0; i < im.width * im.height; ++i) {
        const float boost = rng.next_float() < 0.1f ? 20.0f : 1.0f;
        im.pixels.push_back(boost *
                            glm::vec3(rng.next_float(), rng.next_float(), rng.next_float()));
    }
    return im;
}

/// A rotation by angle a about the unit axis k (Rodrigues).
glm::mat3 rotation(glm::vec3 k, float a) {
    k = glm::normalize(k);
    const glm::mat3 kx(0, k.z, -k.y, -k.z, 0, k.x, k.y, -k.x, 0);  // columns: cross(k, .)
    return glm::mat3(1.0f) + std::sin(a) * kx + (1.0f - std::cos(a)) * kx * kx;
}

/// The lights at infinity: delta sun, soft suns (wide and the real sun's 0.00465 rad),
/// constant and image environments.
std::vector<Named> infinite_lights() {
    const glm::vec3 to_sun(0.3f, 1.0f, -0.2f);
    return {{"delta sun", light_of(DirectionalLight{to_sun, {3, 2, 1}, 0.0f, kScene.radius})},
            {"soft sun", light_of(DirectionalLight{to_sun, {3, 2, 1}, 0.25f, kScene.radius})},
            {"real sun", light_of(DirectionalLight{to_sun, {3, 2, 1}, 0.00465f, kScene.radius})},
            {"constant environment", light_of(EnvironmentLight::constant({0.5f, 1.0f, 2.0f}))},
            {"image environment", light_of(EnvironmentLight::from_image(
                                      random_image(3), rotation({1.0f, 2.0f, 0.5f}, 0.7f), 1.5f))}};
}

std::vector<Named> all_lights() {
    std::vector<Named> all = finite_lights();
    for (Named& l : infinite_lights()) all.push_back(std::move(l));
    return all;
}

/// What a path starting with ray s carries: radiance |cos(normal, direction)| / (pdf_pos
/// pdf_dir), or radiance / pdf_dir for a delta position (whose normal is 0 and pdf_pos 1).
glm::dvec3 weight(const LightLeSample& s) {
    const double c = s.delta_position ? 1.0 : std::fabs(double(glm::dot(s.normal, s.direction)));
    return glm::dvec3(s.radiance) * (c / (double(s.pdf_pos) * double(s.pdf_dir)));
}

/// The mean of n ray weights (an invalid ray weighs 0) and its standard error, from the
/// sample variance.
struct Estimate {
    glm::dvec3 mean{0.0};
    glm::dvec3 se{0.0};
};
Estimate estimate_power(const Light& light, int n, std::uint64_t seed) {
    Pcg32 rng(seed, 17);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int i = 0; i < n; ++i) {
        const glm::vec2 u_pos = rng.next_vec2();
        const glm::vec2 u_dir = rng.next_vec2();
        const LightLeSample s = sample_le(light, kScene, u_pos, u_dir);
        if (!s.valid()) continue;
        const glm::dvec3 w = weight(s);
        sum += w;
        sum2 += w * w;
    }
    Estimate e;
    e.mean = sum / double(n);
    const glm::dvec3 var = glm::max(sum2 / double(n) - e.mean * e.mean, glm::dvec3(0.0));
    e.se = glm::sqrt(var / double(n - 1));
    return e;
}

/// Expects each channel of the estimate within 5 standard errors of `expected`, plus
/// 1e-5 relative: where every weight is the same in exact arithmetic (cosine-weighted area
/// lights, points, the delta sun, a constant environment) the standard error is ~0 and
/// what is left is the float rounding of the weights (~1e-7 relative each).
void expect_estimates(const Estimate& e, const glm::dvec3& expected, const std::string& what) {
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(e.mean[k], expected[k], 5.0 * e.se[k] + 1e-5 * std::fabs(expected[k]))
            << what << ", channel " << k << " (standard error " << e.se[k] << ")";
}

// ---- 1. The rays carry the light's power ----

// E[L |cos| / (pdf_pos pdf_dir)] over the rays of a finite light is the integral of L cos
// over its surface and the hemisphere(s) it emits into, its power; for a point or spot,
// E[I / pdf_dir] is the integral of I over the sphere. power() states both in closed form
// (a spot's checked against quadrature in punctual_light_test.cpp).
TEST(LightEmission, RaysCarryThePowerOfEveryFiniteLight) {
    std::uint64_t seed = 1;
    for (const Named& l : finite_lights()) {
        const Estimate e = estimate_power(l.light, 200000, seed++);
        expect_estimates(e, glm::dvec3(power(l.light)), l.name);
    }
}

// Lights at infinity: a ray's weight L / (pdf_pos pdf_dir) averages to pi R^2 times the
// integral of L over the directions it comes from: the power crossing, per direction, the
// disk of radius R perpendicular to it (what pierces the scene sphere).
TEST(LightEmission, RaysFromLightsAtInfinityCarryThePowerThroughTheSceneDisk) {
    const double r2 = double(kScene.radius) * kScene.radius;
    const std::vector<Named> lights = infinite_lights();
    std::uint64_t seed = 100;
    for (const Named& l : lights) {
        const Estimate e = estimate_power(l.light, 200000, seed++);
        glm::dvec3 expected(0.0);
        if (const auto* sun = std::get_if<DirectionalLight>(&l.light.source)) {
            const glm::dvec3 irradiance(sun->irradiance);
            if (sun->angular_radius == 0.0f) {
                // The delta sun: E pi R^2, its power().
                expected = irradiance * (kPi * r2);
                EXPECT_NEAR(power(l.light).x, expected.x, 1e-6 * expected.x) << l.name;
            } else {
                // A cone of radiance L = E / (pi sin^2 r) over solid angle 2 pi (1 - cos r):
                // L 2 pi (1 - cos r) pi R^2 = E pi R^2 2 / (1 + cos r), slightly above
                // power()'s E pi R^2 (the flux through the one disk facing the axis).
                const double r = sun->angular_radius;
                expected = irradiance / (kPi * std::sin(r) * std::sin(r)) *
                           (2.0 * kPi * (1.0 - std::cos(r))) * (kPi * r2);
            }
        } else {
            const auto& env = std::get<EnvironmentLight>(l.light.source);
            const EnvironmentImage& im = env.data->image;
            if (im.pixels.empty()) {
                // Constant L: 4 pi L pi R^2, which is its power().
                expected = glm::dvec3(env.data->constant) * (4.0 * kPi * kPi * r2);
                EnvironmentLight sized = env;
                sized.scene_radius = kScene.radius;
                EXPECT_NEAR(power(sized).z, expected.z, 1e-5 * expected.z) << l.name;
            } else {
                // Pixel (x, y) spans 2 pi / w in phi and cos(theta) from cos(pi y / h) to
                // cos(pi (y + 1) / h): its solid angle. (power() takes sin(theta) at the
                // row centre instead, an estimate for the light sampler.)
                for (int y = 0; y < im.height; ++y) {
                    const double omega =
                        2.0 * kPi / im.width *
                        (std::cos(kPi * y / im.height) - std::cos(kPi * (y + 1) / im.height));
                    for (int x = 0; x < im.width; ++x)
                        expected += glm::dvec3(im.pixels[std::size_t(y * im.width + x)]) * omega;
                }
                expected *= double(env.scale) * kPi * r2;
            }
        }
        expect_estimates(e, expected, l.name);
    }
}

// A textured triangle's rays carry the texture at their origin: radiance_at of the
// origin's barycentrics, as a ray hitting that point sees.
TEST(LightEmission, TexturedTriangleRaysCarryTheTextureAtTheirOrigin) {
    std::vector<glm::vec3> texels;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            texels.push_back(
                {0.1f + 0.3f * float(x), 0.2f + 0.25f * float(y), 0.05f * float(x * y)});
    TriangleLight tri = triangle({0, 0, 0}, {2, 0.5f, 0}, {0.3f, 1.5f, 1}, {2.0f, 1.0f, 4.0f});
    tri.texture = std::make_shared<const ImageTexture>(4, 4, std::move(texels));
    tri.uv0 = {0.1f, 0.2f};
    tri.uv1 = {0.9f, 0.1f};
    tri.uv2 = {0.4f, 0.95f};
    const glm::vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len2 = glm::dot(c, c);
    Pcg32 rng(7, 1);
    for (int i = 0; i < 4000; ++i) {
        const glm::vec2 u_pos = rng.next_vec2();
        const LightLeSample s = sample_le(light_of(tri), kScene, u_pos, rng.next_vec2());
        ASSERT_TRUE(s.valid());
        // Barycentrics of the origin: sub-triangle areas over the whole.
        const glm::vec3 d = s.origin - tri.p0;
        const glm::vec2 b{glm::dot(glm::cross(d, e2), c) / len2,
                          glm::dot(glm::cross(e1, d), c) / len2};
        const glm::vec3 expected = radiance_at(tri, b);
        for (int k = 0; k < 3; ++k)
            ASSERT_NEAR(s.radiance[k], expected[k], 1e-4f * expected[k] + 1e-6f) << i;
    }
}

// ---- 2. pdf_le gives back the sampled densities ----

/// Whether origin lies on the light's emitting surface (1e-4 relative slack), for the
/// lights that have one; a light at infinity's origin lies on the disk tangent to the scene
/// sphere, perpendicular to the ray.
::testing::AssertionResult origin_on_light(const Light& light, const LightLeSample& s) {
    constexpr float tol = 1e-4f;
    const auto fail = [](const char* what) { return ::testing::AssertionFailure() << what; };
    if (const auto* t = std::get_if<TriangleLight>(&light.source)) {
        const glm::vec3 e1 = t->p1 - t->p0, e2 = t->p2 - t->p0, c = glm::cross(e1, e2);
        const glm::vec3 d = s.origin - t->p0;
        const float b1 = glm::dot(glm::cross(d, e2), c) / glm::dot(c, c);
        const float b2 = glm::dot(glm::cross(e1, d), c) / glm::dot(c, c);
        if (std::fabs(glm::dot(d, glm::normalize(c))) > tol) return fail("off the plane");
        if (b1 < -tol || b2 < -tol || b1 + b2 > 1.0f + tol) return fail("outside the triangle");
    } else if (const auto* q = std::get_if<QuadLight>(&light.source)) {
        const glm::vec3 c = glm::cross(q->edge0, q->edge1), d = s.origin - q->corner;
        const float a = glm::dot(glm::cross(d, q->edge1), c) / glm::dot(c, c);
        const float b = glm::dot(glm::cross(q->edge0, d), c) / glm::dot(c, c);
        if (std::fabs(glm::dot(d, glm::normalize(c))) > tol) return fail("off the plane");
        if (a < -tol || a > 1.0f + tol || b < -tol || b > 1.0f + tol) return fail("outside");
    } else if (const auto* k = std::get_if<DiskLight>(&light.source)) {
        const glm::vec3 d = s.origin - k->center;
        if (std::fabs(glm::dot(d, glm::normalize(k->normal))) > tol) return fail("off the plane");
        if (glm::length(d) > k->radius * (1.0f + tol)) return fail("outside the disk");
    } else if (const auto* sl = std::get_if<SphereLight>(&light.source)) {
        const glm::vec3 d = s.origin - sl->sphere.center;
        if (std::fabs(glm::length(d) - sl->sphere.radius) > tol * sl->sphere.radius)
            return fail("off the sphere");
        if (glm::length(d / sl->sphere.radius - s.normal) > tol) return fail("not the normal");
    } else if (is_infinite(light)) {
        // Tangent plane on the light's side: (origin - center) . -direction = R, and within
        // R of the axis through the centre.
        const glm::vec3 d = s.origin - kScene.center;
        const float along = -glm::dot(d, s.direction);
        const glm::vec3 across = d + along * s.direction;
        if (std::fabs(along - kScene.radius) > tol * kScene.radius) return fail("off the disk");
        if (glm::length(across) > kScene.radius * (1.0f + tol)) return fail("beyond the disk");
    } else if (std::holds_alternative<PointLight>(light.source)) {
        if (s.origin != std::get<PointLight>(light.source).position) return fail("not at it");
    } else if (s.origin != std::get<SpotLight>(light.source).position) {
        return fail("not at the spot");
    }
    return ::testing::AssertionSuccess();
}

// For 4000 rays of every light: valid (rays that graze a surface aside), unit direction
// leaving on the normal's side, origin on the light, the delta flags of the kind, and
// pdf_le at (origin, normal, direction) equal to the sampled pdf_pos and pdf_dir
// (relative 1e-4).
TEST(LightEmission, PdfLeGivesBackTheSampledDensities) {
    Pcg32 rng(21, 4);
    for (const Named& l : all_lights()) {
        const bool point_like = std::holds_alternative<PointLight>(l.light.source) ||
                                std::holds_alternative<SpotLight>(l.light.source);
        const auto* sun = std::get_if<DirectionalLight>(&l.light.source);
        const bool delta_dir = sun != nullptr && sun->angular_radius == 0.0f;
        int valid = 0;
        for (int i = 0; i < 4000; ++i) {
            const glm::vec2 u_pos = rng.next_vec2();
            const LightLeSample s = sample_le(l.light, kScene, u_pos, rng.next_vec2());
            if (!s.valid()) continue;
            ++valid;
            ASSERT_EQ(s.delta_position, point_like) << l.name;
            ASSERT_EQ(s.delta_direction, delta_dir) << l.name;
            ASSERT_NEAR(glm::length(s.direction), 1.0f, 1e-5f) << l.name;
            if (point_like) {
                ASSERT_EQ(s.normal, glm::vec3(0.0f)) << l.name;
                ASSERT_EQ(s.pdf_pos, 1.0f) << l.name;
            } else {
                ASSERT_NEAR(glm::length(s.normal), 1.0f, 1e-5f) << l.name;
                ASSERT_GT(glm::dot(s.normal, s.direction), 0.0f) << l.name;
            }
            ASSERT_TRUE(origin_on_light(l.light, s)) << l.name << ", ray " << i;
            for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(s.radiance[k])) << l.name;
            const LightLePdf p = pdf_le(l.light, kScene, s.origin, s.normal, s.direction);
            ASSERT_NEAR(p.pos, s.pdf_pos, 1e-4f * s.pdf_pos) << l.name << ", ray " << i;
            ASSERT_NEAR(p.dir, s.pdf_dir, 1e-4f * s.pdf_dir) << l.name << ", ray " << i;
        }
        // Only a direction exactly along a surface (u_dir.y = 0) is dropped.
        EXPECT_GE(valid, 3990) << l.name;
    }
}

// One-sided area lights emit nothing behind: no sampled ray leaves the back and pdf_le of
// a direction behind is 0; two-sided ones leave either side about equally often with the
// same density; a sphere emits nothing inward, a spot nothing outside its outer cone, a
// soft sun nothing outside its cone.
TEST(LightEmission, NothingIsEmittedWhereTheLightDoesNotShine) {
    Pcg32 rng(5, 9);
    for (const Named& l : finite_lights()) {
        glm::vec3 front(0.0f);
        bool two_sided = false;
        if (const auto* t = std::get_if<TriangleLight>(&l.light.source)) {
            front = glm::normalize(glm::cross(t->p1 - t->p0, t->p2 - t->p0));
            two_sided = t->two_sided;
        } else if (const auto* q = std::get_if<QuadLight>(&l.light.source)) {
            front = glm::normalize(glm::cross(q->edge0, q->edge1));
            two_sided = q->two_sided;
        } else if (const auto* k = std::get_if<DiskLight>(&l.light.source)) {
            front = glm::normalize(k->normal);
            two_sided = k->two_sided;
        } else {
            continue;
        }
        const int n = 20000;
        int back = 0;
        for (int i = 0; i < n; ++i) {
            const glm::vec2 u_pos = rng.next_vec2();
            const LightLeSample s = sample_le(l.light, kScene, u_pos, rng.next_vec2());
            if (!s.valid()) continue;
            const float c = glm::dot(s.direction, front);
            back += c < 0.0f;
            // The mirror image of the direction through the plane: behind if s is in front.
            const glm::vec3 mirrored = s.direction - 2.0f * c * front;
            const LightLePdf p = pdf_le(l.light, kScene, s.origin, -s.normal, mirrored);
            if (two_sided)
                ASSERT_NEAR(p.dir, s.pdf_dir, 1e-4f * s.pdf_dir) << l.name;
            else
                ASSERT_EQ(p.dir, 0.0f) << l.name;
        }
        if (two_sided)  // binomial(n, 1/2): within 5 standard deviations sqrt(n) / 2
            EXPECT_NEAR(back, n / 2, 5.0 * std::sqrt(double(n)) / 2.0) << l.name;
        else
            EXPECT_EQ(back, 0) << l.name;
    }
    const SphereLight sphere{{{1, 2, 3}, 0.8f}, glm::vec3(1.0f)};
    const glm::vec3 n = glm::normalize(glm::vec3(1, -2, 0.5f));
    const glm::vec3 on = sphere.sphere.center + sphere.sphere.radius * n;
    EXPECT_EQ(pdf_le(light_of(sphere), kScene, on, n, -n).dir, 0.0f);
    EXPECT_GT(pdf_le(light_of(sphere), kScene, on, n, n).dir, 0.0f);

    const SpotLight spot{{0, 2, 0}, {0, -1, 0}, glm::vec3(1.0f), 0.3f, 0.6f};
    const auto at = [](float theta) { return glm::vec3(std::sin(theta), -std::cos(theta), 0.0f); };
    EXPECT_GT(pdf_le(light_of(spot), kScene, spot.position, {}, at(0.59f)).dir, 0.0f);
    EXPECT_EQ(pdf_le(light_of(spot), kScene, spot.position, {}, at(0.61f)).dir, 0.0f);
    EXPECT_EQ(pdf_le(light_of(spot), kScene, spot.position, {}, -at(0.0f)).dir, 0.0f);

    // The soft sun's rays travel away from it: -direction within 0.25 rad of to_light.
    const DirectionalLight sun{{0, 1, 0}, glm::vec3(1.0f), 0.25f, 1.0f};
    const auto from_sun = [](float theta) {
        return glm::vec3(std::sin(theta), -std::cos(theta), 0.0f);
    };
    EXPECT_GT(pdf_le(light_of(sun), kScene, {}, {}, from_sun(0.249f)).dir, 0.0f);
    EXPECT_EQ(pdf_le(light_of(sun), kScene, {}, {}, from_sun(0.251f)).dir, 0.0f);
    EXPECT_EQ(pdf_le(light_of(sun), kScene, {}, {}, -from_sun(0.0f)).dir, 0.0f);
}

// ---- 3. The sampled directions and origins follow the densities (chi-square) ----

/// Counts of n sampled directions of `light` per cell of `bins`, mapped by `to_bin` (the
/// direction as binned; none skips), with a last cell for invalid rays and for directions
/// outside the bins' band, which expects none.
template <class ToBin>
std::vector<double> direction_counts(const Light& light, const DirectionBins& bins, int n,
                                     std::uint64_t seed, ToBin to_bin) {
    Pcg32 rng(seed, 3);
    std::vector<double> observed(std::size_t(bins.size()) + 1, 0.0);
    for (int i = 0; i < n; ++i) {
        const glm::vec2 u_pos = rng.next_vec2();
        const LightLeSample s = sample_le(light, kScene, u_pos, rng.next_vec2());
        const int cell = s.valid() ? bins.cell(to_bin(s)) : -1;
        observed[std::size_t(cell >= 0 ? cell : bins.size())] += 1.0;
    }
    return observed;
}

/// expected_counts with the last cell (invalid or outside) expecting none.
std::vector<double> with_outside_cell(std::vector<double> expected) {
    expected.push_back(0.0);
    return expected;
}

// Directions of a one-sided quad and a two-sided disk over the whole sphere of directions
// (the back half must stay empty for the quad) against pdf_le's density.
TEST(LightEmission, AreaLightDirectionsFollowPdfLeChiSquare) {
    const int n = 200000;
    std::uint64_t seed = 40;
    for (const Named& l : finite_lights()) {
        if (l.name != "one-sided quad" && l.name != "two-sided disk") continue;
        glm::vec3 front;
        if (const auto* q = std::get_if<QuadLight>(&l.light.source))
            front = glm::normalize(glm::cross(q->edge0, q->edge1));
        else
            front = glm::normalize(std::get<DiskLight>(l.light.source).normal);
        DirectionBins bins;
        bins.frame = Frame::from_normal(front);
        bins.n_cos = 16;
        bins.n_phi = 24;
        const auto observed = direction_counts(l.light, bins, n, seed++,
                                               [](const LightLeSample& s) { return s.direction; });
        // Planar lights' direction density does not depend on the origin.
        const auto pdf = [&](const glm::vec3& w) {
            return double(pdf_le(l.light, kScene, glm::vec3(0.0f), front, w).dir);
        };
        expect_chi_square_passes(observed, with_outside_cell(expected_counts(bins, pdf, n)),
                                 l.name);
    }
}

// A sphere light's origins are uniform over the sphere (1 / (4 pi) per steradian of the
// normal), and its directions, in the frame of the normal at their origin, cosine-weighted.
TEST(LightEmission, SphereLightOriginsAndDirectionsFollowTheirDensitiesChiSquare) {
    const SphereLight sl{{{1, 2, 3}, 0.8f}, {2.0f, 1.0f, 0.5f}};
    const int n = 200000;
    DirectionBins whole;
    whole.n_cos = 16;
    whole.n_phi = 24;
    const auto origins = direction_counts(light_of(sl), whole, n, 61, [&](const LightLeSample& s) {
        return glm::normalize(s.origin - sl.sphere.center);
    });
    expect_chi_square_passes(origins,
                             with_outside_cell(expected_counts(
                                 whole, [](const glm::vec3&) { return 1.0 / (4.0 * kPi); }, n)),
                             "sphere light origins");

    DirectionBins upper = whole;
    upper.cos_lo = 0.0;
    const auto local = direction_counts(light_of(sl), upper, n, 62, [](const LightLeSample& s) {
        return Frame::from_normal(s.normal).to_local(s.direction);
    });
    expect_chi_square_passes(
        local,
        with_outside_cell(expected_counts(
            upper, [](const glm::vec3& w) { return std::max(0.0, double(w.z)) / kPi; }, n)),
        "sphere light directions about the normal");
}

// A spot's directions are uniform in its outer cone, a soft sun's uniform in its cone
// (reversed: its rays travel away from it). Bins cover exactly the cone, so a direction
// outside it is an error.
TEST(LightEmission, ConeDirectionsFollowPdfLeChiSquare) {
    const int n = 200000;
    const SpotLight spot{{0, 2, 0}, {0.2f, -1.0f, 0.1f}, {10, 8, 6}, 0.3f, 0.6f};
    DirectionBins cone;
    cone.frame = Frame::from_normal(glm::normalize(spot.direction));
    cone.cos_lo = std::cos(double(spot.outer_angle));
    cone.n_cos = 10;
    cone.n_phi = 24;
    const Light spot_light = light_of(spot);
    const auto observed = direction_counts(spot_light, cone, n, 71,
                                           [](const LightLeSample& s) { return s.direction; });
    expect_chi_square_passes(
        observed,
        with_outside_cell(expected_counts(
            cone,
            [&](const glm::vec3& w) { return double(pdf_le(spot_light, kScene, {}, {}, w).dir); },
            n)),
        "spot");

    const DirectionalLight sun{{0.3f, 1.0f, -0.2f}, {3, 2, 1}, 0.25f, kScene.radius};
    DirectionBins sun_cone = cone;
    sun_cone.frame = Frame::from_normal(glm::normalize(sun.to_light));
    sun_cone.cos_lo = std::cos(double(sun.angular_radius));
    const Light sun_light = light_of(sun);
    const auto toward_sun = direction_counts(sun_light, sun_cone, n, 72,
                                             [](const LightLeSample& s) { return -s.direction; });
    expect_chi_square_passes(
        toward_sun,
        with_outside_cell(expected_counts(
            sun_cone,
            [&](const glm::vec3& w) { return double(pdf_le(sun_light, kScene, {}, {}, -w).dir); },
            n)),
        "soft sun");
}

// ---- 4. Degenerate input ----

/// Expects no ray and finite densities from pdf_le (0 or not, never NaN).
void expect_no_ray(const Light& light, const SceneSphere& scene, const std::string& what) {
    Pcg32 rng(9, 9);
    for (int i = 0; i < 64; ++i) {
        const glm::vec2 u_pos = rng.next_vec2();
        const LightLeSample s = sample_le(light, scene, u_pos, rng.next_vec2());
        EXPECT_FALSE(s.valid()) << what;
        const LightLePdf p =
            pdf_le(light, scene, glm::vec3(0.0f), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1));
        EXPECT_TRUE(std::isfinite(p.pos) && std::isfinite(p.dir)) << what;
    }
}

TEST(LightEmission, DegenerateLightsGiveNoRayAndNoNaN) {
    const glm::vec3 L(1.0f);
    expect_no_ray(light_of(triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, L)), kScene,
                  "collinear triangle");
    expect_no_ray(light_of(triangle({0, 0, 0}, {1, 0, 0}, {0, kNaN, 0}, L)), kScene,
                  "NaN triangle");
    expect_no_ray(light_of(QuadLight{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, L}), kScene,
                  "parallel quad edges");
    expect_no_ray(light_of(QuadLight{{0, 0, 0}, {kInf, 0, 0}, {0, 1, 0}, L}), kScene,
                  "infinite quad");
    expect_no_ray(light_of(DiskLight{{0, 0, 0}, {0, 1, 0}, 0.0f, L}), kScene, "zero radius");
    expect_no_ray(light_of(DiskLight{{0, 0, 0}, {0, 1, 0}, kNaN, L}), kScene, "NaN radius");
    expect_no_ray(light_of(DiskLight{{0, 0, 0}, {0, 0, 0}, 1.0f, L}), kScene, "zero normal");
    expect_no_ray(light_of(SphereLight{{{0, 0, 0}, 0.0f}, L}), kScene, "zero sphere");
    expect_no_ray(light_of(SphereLight{{{0, 0, 0}, -1.0f}, L}), kScene, "negative sphere");
    expect_no_ray(light_of(SphereLight{{{0, 0, 0}, 1e-30f}, L}), kScene, "1 / area overflows");
    expect_no_ray(light_of(SphereLight{{{kNaN, 0, 0}, 1.0f}, L}), kScene, "NaN sphere");
    expect_no_ray(light_of(PointLight{{kNaN, 0, 0}, L}), kScene, "NaN point");
    expect_no_ray(light_of(SpotLight{{0, 0, 0}, {0, 0, 0}, L, 0.1f, 0.5f}), kScene,
                  "spot without direction");
    expect_no_ray(light_of(SpotLight{{0, 0, 0}, {0, 1, 0}, L, 0.0f, 0.0f}), kScene,
                  "spot without cone");
    expect_no_ray(light_of(SpotLight{{0, 0, 0}, {0, 1, 0}, L, 0.0f, kNaN}), kScene, "NaN cone");
    expect_no_ray(light_of(DirectionalLight{{0, 0, 0}, L, 0.0f}), kScene, "sun without direction");
    expect_no_ray(light_of(DirectionalLight{{0, 0, 0}, L, 0.1f}), kScene, "soft sun, no direction");
    expect_no_ray(light_of(EnvironmentLight{}), kScene, "environment without data");
    // Lights at infinity need a scene sphere of finite centre and radius > 0.
    for (const Named& l : infinite_lights()) {
        expect_no_ray(l.light, {{0, 0, 0}, 0.0f}, l.name + ", scene radius 0");
        expect_no_ray(l.light, {{0, 0, 0}, kInf}, l.name + ", scene radius inf");
        expect_no_ray(l.light, {{0, 0, 0}, kNaN}, l.name + ", scene radius NaN");
        expect_no_ray(l.light, {{kNaN, 0, 0}, 1.0f}, l.name + ", scene centre NaN");
    }
    // Extreme sample numbers on good lights: a ray or none, never a NaN.
    for (const Named& l : all_lights())
        for (const float a : {0.0f, 0.5f, 0x1.fffffep-1f})
            for (const float b : {0.0f, 0.25f, 0x1.fffffep-1f}) {
                const LightLeSample s = sample_le(l.light, kScene, {a, b}, {b, a});
                if (!s.valid()) continue;
                const float sum = s.origin.x + s.origin.y + s.origin.z + s.direction.x +
                                  s.direction.y + s.direction.z + s.normal.x + s.normal.y +
                                  s.normal.z + s.radiance.x + s.radiance.y + s.radiance.z +
                                  s.pdf_pos + s.pdf_dir;
                EXPECT_TRUE(std::isfinite(sum)) << l.name << " at " << a << ", " << b;
            }
}

// ---- The scene's bounding sphere ----

// Scene::bounding_sphere is the box's centre and half diagonal, the radius commit() gives
// lights at infinity: rays from it carry the delta sun's power() exactly.
TEST(LightEmission, SceneBoundingSphereSizesLightsAtInfinity) {
    EXPECT_EQ(Scene().bounding_sphere().radius, 1.0f);
    Scene scene;
    TriangleMesh mesh;
    mesh.positions = {{-1, 0, -2}, {3, 0, -2}, {3, 2, 2}, {-1, 2, 2}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(mesh, scene.add_material(Material::diffuse(glm::vec3(0.5f))));
    scene.add_directional_light({{0.3f, 1.0f, -0.2f}, {3, 2, 1}, 0.0f});
    scene.commit();
    const SceneSphere sphere = scene.bounding_sphere();
    EXPECT_LT(glm::length(sphere.center - glm::vec3(1, 1, 0)), 1e-5f);
    EXPECT_FLOAT_EQ(sphere.radius, 3.0f);  // half of sqrt(4^2 + 2^2 + 4^2)
    const Light& sun = scene.lights()[0];
    Pcg32 rng(3, 3);
    for (int i = 0; i < 100; ++i) {
        const glm::vec2 u_pos = rng.next_vec2();
        const LightLeSample s = sample_le(sun, sphere, u_pos, rng.next_vec2());
        ASSERT_TRUE(s.valid());
        const glm::dvec3 w = weight(s);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(w[k], power(sun)[k], 1e-5 * power(sun)[k]);
    }
}

}  // namespace
}  // namespace librt
