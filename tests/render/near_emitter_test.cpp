// Emissive triangles close to a surface (issue 12's two-sided ceiling panel, 1 cm under
// the ceiling): triangle lights are sampled over their solid angle (Arvo 1995), so a light
// sample's weight L cos / pdf = L cos omega stays below 2 pi L however close the point is.
// The irradiance from both faces equals Lambert's polygon formula, sample_li's points lie
// on the triangle at the reported distance with pdf_li's density, and the MIS path tracer
// equals the brute-force one on a room whose two-sided panel hangs just under the ceiling.

#include "light_scene_test_util.h"
#include "sampling/spherical_triangle.h"
#include "scene/shadow_ray.h"

#include <librt/geometry/ray_offset.h>
#include <librt/integrator/integrators.h>
#include <librt/light/triangle_light.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace librt {
namespace {

using testing::expect_mis_equals_brute;
using testing::lambert_polygon_irradiance;

TriangleLight triangle(bool two_sided) {
    TriangleLight t;
    // cross(p1 - p0, p2 - p0) = (0, -0.5, 0): the front faces down.
    t.p0 = {-0.5f, 1.99f, -0.5f};
    t.p1 = {0.5f, 1.99f, -0.5f};
    t.p2 = {0.0f, 1.99f, 0.5f};
    t.radiance = glm::vec3(4.0f);
    t.two_sided = two_sided;
    return t;
}

struct Case {
    glm::vec3 p, n;
    const char* what;
};

// Points 1 cm from the panel on either side (the ceiling above it, facing down, and just
// outside its edge), and one far below, facing up.
const Case kCases[] = {
    {{0.0f, 2.0f, -0.1f}, {0, -1, 0}, "ceiling 1 cm above (back face)"},
    {{0.1f, 2.0f, 0.45f}, {0, -1, 0}, "ceiling beside the edge (back face, grazing)"},
    {{0.0f, 1.98f, 0.0f}, {0, 1, 0}, "1 cm below, facing up (front face)"},
    {{0.3f, 0.0f, 0.2f}, {0, 1, 0}, "floor (front face, far)"},
};

TEST(NearEmitter, IrradianceFromBothFacesMatchesLambertWithBoundedWeights) {
    const TriangleLight tri = triangle(true);
    const std::vector<glm::dvec3> v{glm::dvec3(tri.p0), glm::dvec3(tri.p1), glm::dvec3(tri.p2)};
    for (const Case& k : kCases) {
        const Light light{tri, kInvalidId};
        const auto e = testing::irradiance_by_sampling(light, k.p, k.n, 50000, 3);
        const double expected =
            lambert_polygon_irradiance(v, glm::dvec3(k.p), glm::dvec3(k.n), 4.0);
        EXPECT_GT(expected, 1e-3) << k.what;
        EXPECT_NEAR(e.mean.x, expected, 5.0 * e.se.x + 1e-6 * expected) << k.what;
        // Solid-angle sampling: every weight L cos / pdf is at most L omega <= 2 pi L (area
        // sampling's d^2 / (A cos) made single weights ~10^3 L at 1 cm).
        Pcg32 rng(5, 1);
        float worst = 0.0f;
        for (int i = 0; i < 20000; ++i) {
            const LightLiSample s = sample_li(tri, k.p, {rng.next_float(), rng.next_float()});
            if (!s.valid()) continue;
            worst = std::max(worst, s.radiance.x * std::max(0.0f, glm::dot(k.n, s.wi)) / s.pdf);
        }
        EXPECT_LE(worst, 4.0f * 2.0f * std::numbers::pi_v<float> * 1.0001f) << k.what;
    }
}

TEST(NearEmitter, SamplesLieOnTheTriangleAtTheirDistanceWithPdfLiDensity) {
    for (const bool two_sided : {true, false}) {
        const TriangleLight tri = triangle(two_sided);
        const glm::vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
        const glm::vec3 n = glm::normalize(glm::cross(e1, e2));
        for (const Case& k : kCases) {
            const bool behind = glm::dot(k.p - tri.p0, n) < 0.0f;
            Pcg32 rng(9, 2);
            int valid = 0;
            for (int i = 0; i < 4000; ++i) {
                const LightLiSample s = sample_li(tri, k.p, {rng.next_float(), rng.next_float()});
                if (!s.valid()) continue;
                ++valid;
                // The direction meets the triangle; the shadow ray's distance ends short of
                // its plane by the rounding of a test against it (ray_offset_scale of its
                // largest vertex coordinates over |cos| at the emitter), then by the
                // relative kShadowEpsilon, never beyond; end_slope is 1 / |cos|.
                const float dn = glm::dot(s.wi, n);
                const float t = glm::dot(tri.p0 - k.p, n) / dn;
                const glm::vec3 q = k.p + t * s.wi - tri.p0;
                const glm::vec3 largest =
                    glm::max(glm::max(glm::abs(tri.p0), glm::abs(tri.p1)), glm::abs(tri.p2));
                const float margin = ray_offset_scale(largest) / std::fabs(dn);
                EXPECT_NEAR(s.end_slope, 1.0f / std::fabs(dn), 1e-5f / std::fabs(dn)) << k.what;
                EXPECT_LE(s.distance, t) << k.what;
                EXPECT_NEAR(s.distance, std::max(0.0f, (t - margin) * (1.0f - kShadowEpsilon)),
                            1e-5f * t)
                    << k.what;
                const float b1 = glm::dot(glm::cross(q, e2), n) / glm::length(glm::cross(e1, e2));
                const float b2 = glm::dot(glm::cross(e1, q), n) / glm::length(glm::cross(e1, e2));
                EXPECT_GE(b1, -1e-4f) << k.what;
                EXPECT_GE(b2, -1e-4f) << k.what;
                EXPECT_LE(b1 + b2, 1.0f + 1e-4f) << k.what;
                EXPECT_NEAR(pdf_li(tri, k.p, s.wi), s.pdf, 2e-3f * s.pdf) << k.what;
            }
            // A one-sided (front = down) triangle gives nothing behind it and every sample in
            // front; a two-sided one every sample on both sides.
            EXPECT_EQ(valid, behind && !two_sided ? 0 : 4000) << k.what << " " << two_sided;
        }
    }
}

TEST(NearEmitter, SolidAngleDensityIntegratesToOneOverTheTriangle) {
    // pdf_li over all directions (uniform sphere estimator) integrates to 1 where sampled by
    // solid angle (near) and by area (far).
    const TriangleLight tri = triangle(true);
    for (const Case& k : {kCases[0], kCases[2], kCases[3]}) {
        Pcg32 rng(21, 4);
        constexpr int count = 400000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < count; ++i) {
            // Uniform direction on the sphere (Archimedes: z uniform in [-1, 1]).
            const float z = 1.0f - 2.0f * rng.next_float();
            const float phi = 2.0f * std::numbers::pi_v<float> * rng.next_float();
            const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
            const double v = 4.0 * std::numbers::pi *
                             pdf_li(tri, k.p, {r * std::cos(phi), z, r * std::sin(phi)});
            sum += v;
            sum2 += v * v;
        }
        const double mean = sum / count, se = std::sqrt((sum2 / count - mean * mean) / count);
        EXPECT_NEAR(mean, 1.0, 5.0 * se + 1e-3) << k.what;
    }
}

// A ceiling with a two-sided panel 1 cm under it.
Scene ceiling_and_panel() {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.73f)));
    TriangleMesh ceiling;
    ceiling.positions = {{-2, 2, -2}, {2, 2, -2}, {2, 2, 2}, {-2, 2, 2}};
    ceiling.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(ceiling, white);
    TriangleMesh lamp;
    lamp.positions = {{-0.25f, 1.99f, -0.25f},
                      {0.25f, 1.99f, -0.25f},
                      {0.25f, 1.99f, 0.25f},
                      {-0.25f, 1.99f, 0.25f}};
    lamp.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(lamp, scene.add_material(Material::emissive(glm::vec3(17.0f))));
    scene.commit();
    return scene;
}

// The path loop's shadow ray (spawn_ray_to from the offset origin, the light's object not
// skipped: triangle lights have none) toward every light sample from the ceiling beside the
// panel is free: the panel must not shadow its own light (before the shadow distance's
// margin, 999 of 1000 such rays ended on the panel and the ceiling got no direct light).
TEST(NearEmitter, ShadowRaysFromBesideThePanelDoNotEndOnIt) {
    const Scene scene = ceiling_and_panel();
    // Rays straight up to the ceiling 9 mm and 1 cm beside the panel's edges, and inside the
    // gap above it: the surface points as the path loop gets them, from a hit.
    for (const glm::vec3 o : {glm::vec3(-0.2593f, 1.0f, 0.1437f), glm::vec3(0.26f, 1.0f, 0.0f),
                              glm::vec3(0.05f, 1.995f, -0.1f)}) {
        Ray r;
        r.origin = o;
        r.direction = {0.0f, 1.0f, 0.0f};
        Hit hit;
        ASSERT_TRUE(scene.intersect(r, hit));
        ASSERT_NEAR(hit.point.y, 2.0f, 1e-5f);
        const glm::vec3 p = hit.point;
        Pcg32 rng(4, 4);
        int valid = 0, blocked = 0;
        for (int i = 0; i < 2000; ++i) {
            const Light& light = scene.lights()[std::size_t(i % 2)];
            const LightLiSample s =
                sample_li(light, hit.point, {rng.next_float(), rng.next_float()});
            if (!s.valid()) continue;
            ++valid;
            if (scene.occluded(spawn_ray_to(hit.point, hit.geometric_normal, hit.offset, s.wi,
                                            s.distance, s.end_slope),
                               light.object))
                ++blocked;
        }
        EXPECT_GT(valid, 0) << p.x << " " << p.y << " " << p.z;
        EXPECT_EQ(blocked, 0) << "of " << valid << " at " << p.x << " " << p.y << " " << p.z;
    }
}

// A room (floor, ceiling at y = 2, back wall) with a two-sided emissive panel 2 cm under
// the ceiling: the case whose gap the area sampler could not handle.
TEST(NearEmitter, MisEqualsBruteForceWithATwoSidedPanelUnderTheCeiling) {
    Scene scene;
    testing::add_floor_and_ball(scene);
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.73f)));
    TriangleMesh ceiling;
    ceiling.positions = {{-2, 2, -2}, {2, 2, -2}, {2, 2, 2}, {-2, 2, 2}};
    ceiling.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(ceiling, white);
    TriangleMesh back;
    back.positions = {{-2, 0, -2}, {2, 0, -2}, {2, 2, -2}, {-2, 2, -2}};
    back.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(back, white);
    TriangleMesh lamp;
    lamp.positions = {
        {-0.4f, 1.98f, -0.4f}, {0.4f, 1.98f, -0.4f}, {0.4f, 1.98f, 0.4f}, {-0.4f, 1.98f, 0.4f}};
    lamp.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(lamp, scene.add_material(Material::emissive(glm::vec3(5.0f, 4.0f, 3.0f))));
    scene.commit();
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 512, "two-sided panel, top");
    expect_mis_equals_brute(scene, testing::side_camera(), 32, 512, "two-sided panel, side");
    // Straight up at the panel and the ceiling around it, lit by the panel's back face.
    testing::Pinhole up;
    up.eye = {0.1f, 1.0f, 0.05f};
    up.forward = {0.0f, 1.0f, 0.0f};
    up.up = {0.0f, 0.0f, -1.0f};
    up.width = up.height = 12;
    expect_mis_equals_brute(scene, up, 32, 512, "two-sided panel, from below");
}

}  // namespace
}  // namespace librt

namespace librt {
namespace {

// A point of an emitting panel does not light itself. The panel (two triangles of a glTF
// material: black base colour, so only its specular layer reflects, and an emission) is
// alone in the scene: the radiance leaving it toward the camera is its emission and
// nothing else (no other surface to reflect). Spherical-triangle sampling from a point on
// the panel, 10^-7 off its plane by rounding, spans a hemisphere with a shadow ray too
// short to meet anything: before, PathTracer added that reflection (1 % of L here).
TEST(NearEmitter, APanelDoesNotLightItself) {
    Scene scene;
    TriangleMesh panel;
    panel.positions = {{-0.25f, 1.99f, -0.25f},
                       {0.25f, 1.99f, -0.25f},
                       {0.25f, 1.99f, 0.25f},
                       {-0.25f, 1.99f, 0.25f}};
    panel.triangles = {{0, 1, 2}, {0, 2, 3}};
    Material light = Material::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.5f);
    light.emission = glm::vec3(15.0f);
    scene.add_mesh(panel, scene.add_material(light));
    scene.commit();
    PathTracerSettings settings;
    settings.max_depth = 3;
    settings.russian_roulette = false;
    const PathTracer tracer(settings);
    Pcg32 rng(5, 9);
    for (int i = 0; i < 2000; ++i) {
        // Rays from below at varied points and angles.
        Ray ray;
        ray.origin = {rng.next_float() - 0.5f, 1.0f, rng.next_float() - 0.5f};
        const glm::vec3 target{0.4f * rng.next_float() - 0.2f, 1.99f,
                               0.4f * rng.next_float() - 0.2f};
        ray.direction = glm::normalize(target - ray.origin);
        Sampler sampler(SamplerKind::Independent, 0, 0, std::uint32_t(i), 3);
        const glm::vec3 l = tracer.li(scene, ray, sampler);
        ASSERT_EQ(l, glm::vec3(15.0f)) << "ray " << i;
    }
    // The light seam itself: nothing to sample, and no density, from a point of the panel.
    TriangleLight tl;
    tl.p0 = panel.positions[0];
    tl.p1 = panel.positions[1];
    tl.p2 = panel.positions[2];
    tl.radiance = glm::vec3(15.0f);
    const glm::vec3 on{0.1f, 1.99f, -0.1f};
    EXPECT_FALSE(sample_li(tl, on, {0.3f, 0.6f}).valid());
    EXPECT_EQ(pdf_li(tl, on, glm::normalize(glm::vec3(0.2f, 1e-3f, 0.1f))), 0.0f);
}

}  // namespace
}  // namespace librt
