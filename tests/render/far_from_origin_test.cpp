// Light transport away from the world origin (issue 41): the same scene rendered where it is
// and translated far away gives the same image within noise, and a furnace whose huge wall
// passes next to the origin returns its closed form. A self-intersecting spawn loses its
// path (the ray starts behind the surface and escapes, or hits the surface at once), so
// both fail when the ray offset does not cover the error of the hit.

#include "integrator_test_util.h"
#include "sampling/sanitizer_scale.h"

#include <librt/integrator/integrators.h>
#include <librt/light/sphere_light.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace librt {
namespace {

using testing::Pinhole;
using testing::region;
using testing::render_stats;
using testing::StatImage;

/// The axis-aligned box [lo, hi] as 12 triangles facing inward, the top face (y = hi.y)
/// with material `top`, the others `walls`.
void add_closed_box(Scene& scene, const glm::vec3& lo, const glm::vec3& hi, std::uint32_t walls,
                    std::uint32_t top) {
    const auto corner = [&](int i) {
        return glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    };
    // Each face as corner indices in an order whose winding faces the inside; the scene's
    // materials are two-sided for diffuse, so only the quads' planes matter here.
    const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                             {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    for (int f = 0; f < 6; ++f) {
        const std::uint32_t m = f == 3 ? top : walls;  // face 3 is y = hi.y
        const glm::vec3 a = corner(faces[f][0]), b = corner(faces[f][1]), c = corner(faces[f][2]),
                        d = corner(faces[f][3]);
        scene.add_triangle({a, b, c}, m);
        scene.add_triangle({a, c, d}, m);
    }
}

/// Per-pixel statistics of `spp` samples of the integrator, each through a point uniform
/// over its pixel (pixel-centre rays would put every sample of a pixel on one point, and a
/// point that rounding moves across an edge changes the pixel's value: not noise).
StatImage render_jittered(const Scene& scene, Integrator& integrator, const Pinhole& cam, int spp,
                          std::uint64_t seed, float t_min = 0.0f) {
    integrator.preprocess(scene);
    StatImage img{cam.width, cam.height,
                  std::vector<testing::PixelStats>(std::size_t(cam.width * cam.height))};
    const glm::vec3 right = glm::cross(cam.forward, cam.up);
    const float depth = float(cam.height) / (2.0f * std::tan(glm::radians(cam.fov_degrees) * 0.5f));
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            Pcg32 jitter(seed * 7919u + std::uint64_t(y * cam.width + x), 17);
            testing::PixelStats& p = img.pixels[std::size_t(y * cam.width + x)];
            for (int s = 0; s < spp; ++s) {
                const float px = float(x) - float(cam.width) / 2.0f + jitter.next_float();
                const float py = -float(y) + float(cam.height) / 2.0f - jitter.next_float();
                Ray ray;
                ray.origin = cam.eye;
                ray.direction = glm::normalize(px * right + py * cam.up + depth * cam.forward);
                ray.t_min = t_min;
                Sampler sampler(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s), seed);
                p.add(integrator.li(scene, ray, sampler));
            }
        }
    return img;
}

/// A closed diffuse box 10 across with an emissive ceiling (triangle lights), the camera
/// inside it, all shifted by `shift`; per-pixel statistics of a PathTracer render.
StatImage render_box(const glm::vec3& shift, int spp, std::uint64_t seed) {
    Scene scene;
    const auto walls = scene.add_material(Material::diffuse(glm::vec3(0.7f, 0.6f, 0.5f)));
    Material light = Material::diffuse(glm::vec3(0.5f));
    light.emission = glm::vec3(2.0f);
    const auto top = scene.add_material(light);
    add_closed_box(scene, shift, shift + glm::vec3(10.0f), walls, top);
    // A ball in the room, for shadows and edges.
    scene.add_sphere({shift + glm::vec3(4.0f, 2.0f, 5.0f), 2.0f}, walls);
    scene.commit();
    Pinhole cam;
    cam.eye = shift + glm::vec3(5.0f, 5.0f, 9.5f);
    cam.fov_degrees = 90.0f;
    cam.width = cam.height = 32;
    PathTracer path({5, false});
    return render_jittered(scene, path, cam, spp, seed);
}

// The box at the origin and shifted by 1e2, 1e3 and 1e4 along every axis (and by 0, with
// another seed: the statistic's own control): each 4x4 block's mean agrees within 5
// standard errors of the difference, and the blocks' chi^2 (64 degrees of freedom) stays
// below 120, P ~ 3e-5. The renders use different seeds, so the two estimates are
// independent and their difference has variance se_a^2 + se_b^2.
TEST(FarFromOrigin, ATranslatedBoxRendersTheSameImage) {
    const int spp = testing::scaled_samples(64);
    const StatImage at_origin = render_box(glm::vec3(0.0f), spp, 1);
    for (const float shift : {0.0f, 1e2f, 1e3f, 1e4f}) {
        const StatImage far = render_box(glm::vec3(shift), spp, 2 + std::uint64_t(shift));
        double chi2 = 0.0;
        int terms = 0;
        for (int by = 0; by < 32; by += 4)
            for (int bx = 0; bx < 32; bx += 4) {
                const auto a = region(at_origin, bx, by, bx + 4, by + 4);
                const auto b = region(far, bx, by, bx + 4, by + 4);
                // Luminance-like sum of the channels: one term per block.
                const double da = a.mean.x + a.mean.y + a.mean.z;
                const double db = b.mean.x + b.mean.y + b.mean.z;
                // The channels of one block are correlated, so the sum's variance is at most
                // (sum of the standard errors)^2.
                const double se_a = std::sqrt(a.se2.x) + std::sqrt(a.se2.y) + std::sqrt(a.se2.z);
                const double se_b = std::sqrt(b.se2.x) + std::sqrt(b.se2.y) + std::sqrt(b.se2.z);
                const double var = se_a * se_a + se_b * se_b;
                ASSERT_GT(var, 0.0);
                EXPECT_LE(std::fabs(da - db), 5.0 * std::sqrt(var))
                    << "shift " << shift << " block (" << bx << ", " << by << "): " << da
                    << " at the origin, " << db << " shifted";
                chi2 += (da - db) * (da - db) / var;
                ++terms;
            }
        std::printf("shift %g: chi^2 %.1f over %d blocks\n", double(shift), chi2, terms);
        // 64 degrees of freedom: P(chi^2 > 120) ~ 3e-5 (the variances above are upper
        // bounds, which only lowers chi^2 of an unbiased difference).
        EXPECT_LT(chi2, 120.0) << "shift " << shift;
    }
}

/// smallpt's room (Beason 2007: walls as spheres of radius 1e5, the room between x = 1 and
/// 99, y = 0 and 81.6, z = 0 and 170; a light sphere of radius 600 buried in the ceiling
/// but for a cap), its walls in double, shifted by `shift`; smallpt's camera (at (50, 52,
/// 295.6), outside the front wall, its rays starting 140 along) looking into the back-wall
/// corner at (1, 0, 0), the room's point nearest the world origin, ~300 away: a long ray,
/// whose o + t d is rounded far more than a point near the origin.
StatImage render_smallpt_corner(double shift, int spp, std::uint64_t seed) {
    Scene scene;
    const auto diffuse = [&](glm::vec3 c) { return scene.add_material(Material::diffuse(c)); };
    const glm::dvec3 s(shift);
    scene.add_sphere(s + glm::dvec3(1e5 + 1, 40.8, 81.6), 1e5, diffuse({0.75f, 0.25f, 0.25f}));
    scene.add_sphere(s + glm::dvec3(-1e5 + 99, 40.8, 81.6), 1e5, diffuse({0.25f, 0.25f, 0.75f}));
    scene.add_sphere(s + glm::dvec3(50, 40.8, -1e5), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere(s + glm::dvec3(50, 40.8, 1e5 + 170), 1e5, diffuse(glm::vec3(0.0f)));
    scene.add_sphere(s + glm::dvec3(50, 1e5, 81.6), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere(s + glm::dvec3(50, -1e5 + 81.6, 81.6), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere_light(SphereLight{
        Sphere{glm::vec3(s + glm::dvec3(50, 681.6 - 0.27, 81.6)), 600.0f}, glm::vec3(12.0f)});
    scene.commit();
    Pinhole cam;
    const glm::dvec3 eye = s + glm::dvec3(50.0, 52.0, 295.6);
    cam.eye = glm::vec3(eye);
    cam.forward = glm::vec3(glm::normalize(s + glm::dvec3(1.0, 0.0, 0.0) - eye));
    cam.up = glm::normalize(glm::vec3(0, 1, 0) -
                            glm::dot(glm::vec3(0, 1, 0), cam.forward) * cam.forward);
    cam.fov_degrees = 3.0f;
    cam.width = cam.height = 16;
    PathTracer path({5, false});
    return render_jittered(scene, path, cam, spp, seed, 140.0f);
}

// The corner of smallpt's room nearest the origin is as bright as the same corner with the
// room shifted by 100 along every axis (where the issue found it right): the whole view's
// mean within 5 standard errors and each 4x4 block within 5 (the corner was 14.7 % dark
// over a 28-pixel patch, from rays spawned behind the left wall).
TEST(FarFromOrigin, SmallptCornerNearTheOriginIsAsBrightAsShifted) {
    const int spp = testing::scaled_samples(256);
    const StatImage near = render_smallpt_corner(0.0, spp, 5);
    const StatImage shifted = render_smallpt_corner(100.0, spp, 6);
    const auto compare = [&](int x0, int y0, int x1, int y1) {
        const auto a = region(near, x0, y0, x1, y1);
        const auto b = region(shifted, x0, y0, x1, y1);
        for (int c = 0; c < 3; ++c) {
            const double se = std::sqrt(a.se2[c] + b.se2[c]);
            EXPECT_GT(se, 0.0);
            EXPECT_LE(std::fabs(a.mean[c] - b.mean[c]), 5.0 * se)
                << "pixels [" << x0 << ", " << x1 << ") x [" << y0 << ", " << y1 << ") channel "
                << c << ": " << a.mean[c] << " near the origin, " << b.mean[c] << " shifted";
        }
        return a.mean.x / b.mean.x;
    };
    std::printf("smallpt corner: near / shifted = %.4f\n", compare(0, 0, 16, 16));
    for (int by = 0; by < 16; by += 4)
        for (int bx = 0; bx < 16; bx += 4) compare(bx, by, bx + 4, by + 4);
}

// White furnace in an enclosure whose wall passes within 1 of the origin: every surface
// emits Le and reflects albedo a (diffuse), so radiance is Le / (1 - a) everywhere and a path
// cut after D bounces carries Le (1 - a^(D+1)) / (1 - a). BruteForcePathTracer (cosine
// sampling of a constant albedo, no light sampling) carries exactly that on every path, so
// every pixel must equal it to float accuracy: a path lost to a self-hit (its ray starting
// behind the wall) carries less. PathTracer, whose light samples of emissive triangles add
// variance, must give it within 5 standard errors over the image.
void expect_furnace(const Scene& scene, const glm::vec3& eye, const glm::vec3& forward,
                    const char* what) {
    Pinhole cam;
    cam.eye = eye;
    cam.forward = forward;
    cam.up = std::fabs(forward.y) > 0.5f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    cam.fov_degrees = 100.0f;
    cam.width = cam.height = 16;
    const int depth = 20;
    const double a = 0.5, le = 1.0;
    const double expected = le * (1.0 - std::pow(a, depth + 1)) / (1.0 - a);
    const int spp = testing::scaled_samples(64);
    BruteForcePathTracer brute({depth, false});
    const StatImage exact = render_stats(scene, brute, cam, spp, 3);
    int off = 0;
    double lowest = expected;
    for (const auto& p : exact.pixels) {
        const double v = p.mean().x;
        if (std::fabs(v - expected) > 1e-4 * expected) ++off;
        lowest = std::min(lowest, v);
    }
    EXPECT_EQ(off, 0) << what << ": pixels off the furnace value " << expected << ", lowest "
                      << lowest;
    PathTracer path({depth, false});
    const StatImage img = render_stats(scene, path, cam, spp, 4);
    const auto all = region(img, 0, 0, cam.width, cam.height);
    EXPECT_NEAR(all.mean.x, expected, 5.0 * std::sqrt(all.se2.x) + 1e-5 * expected) << what;
}

Material furnace_material() {
    Material m = Material::diffuse(glm::vec3(0.5f));
    m.emission = glm::vec3(1.0f);
    return m;
}

TEST(FarFromOrigin, FurnaceInsideAHugeSphereNextToTheOrigin) {
    Scene scene;
    // Radius 1e5, its surface at x = 1 (smallpt's left wall), the camera just inside it.
    scene.add_sphere(glm::dvec3(1.0 + 1e5, 0.0, 0.0), 1e5, scene.add_material(furnace_material()));
    scene.commit();
    expect_furnace(scene, {2.0f, 0.5f, 0.25f}, {-1.0f, 0.0f, 0.0f}, "sphere");
}

TEST(FarFromOrigin, FurnaceInsideAHugeTriangleBoxNextToTheOrigin) {
    Scene scene;
    const auto m = scene.add_material(furnace_material());
    // A box 2e5 across, one face at x = 1 passing next to the origin: its triangles' vertices
    // are 1e5 away from the points hit there.
    add_closed_box(scene, {1.0f, -1e5f, -1e5f}, {1.0f + 2e5f, 1e5f, 1e5f}, m, m);
    scene.commit();
    expect_furnace(scene, {2.0f, 0.5f, 0.25f}, {-1.0f, 0.0f, 0.0f}, "triangle box");
}

}  // namespace
}  // namespace librt
