// Integrators: analytic cases, the white furnace, PathTracer against the brute-force
// reference on the report's room, point light against a tiny sphere light, and scenes
// built to provoke NaN. Tolerances come from the sample variance (see integrator_test_util.h).

#include "integrator_test_util.h"

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace librt {
namespace {

using testing::add_room;
using testing::Pinhole;
using testing::region;
using testing::render_stats;
using testing::room_camera;
using testing::StatImage;

// A floor quad at y = 0 facing +y, half-size s.
void add_floor(Scene& scene, float s, std::uint32_t material) {
    scene.add_triangle({{-s, 0, -s}, {-s, 0, s}, {s, 0, s}}, material);
    scene.add_triangle({{-s, 0, -s}, {s, 0, s}, {s, 0, -s}}, material);
}

// |a - b| <= k * sqrt(se_a^2 + se_b^2) + rel * max(|a|, |b|) per channel.
void expect_same(const testing::RegionEstimate& a, const testing::RegionEstimate& b, double k,
                 double rel, const std::string& where) {
    for (int c = 0; c < 3; ++c) {
        const double tol = k * std::sqrt(a.se2[c] + b.se2[c]) +
                           rel * std::max(std::fabs(a.mean[c]), std::fabs(b.mean[c]));
        EXPECT_LE(std::fabs(a.mean[c] - b.mean[c]), tol)
            << where << " channel " << c << ": " << a.mean[c] << " vs " << b.mean[c] << " (se "
            << std::sqrt(a.se2[c]) << ", " << std::sqrt(b.se2[c]) << ")";
    }
}

TEST(Integrators, SettingsAreValidated) {
    auto message = [](const auto& make) {
        try {
            make();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message([] { PathTracer({-1}); }).find("max_depth = -1"), std::string::npos);
    EXPECT_NE(message([] { BruteForcePathTracer({1001}); }).find("max_depth = 1001"),
              std::string::npos);
    EXPECT_NE(message([] { DirectLighting({-3}); }).find("max_depth = -3"), std::string::npos);
    EXPECT_NE(message([] {
                  PathTracer({5, true, -1});
              }).find("russian_roulette_depth"),
              std::string::npos);
    EXPECT_NO_THROW(PathTracer({1000}));
    EXPECT_EQ(PathTracer().settings().max_depth, 1000);  // issue 15: converging defaults
    EXPECT_TRUE(PathTracer().settings().russian_roulette);
}

// White furnace: the camera inside a closed sphere of albedo a emitting Le everywhere.
// Radiance is the same everywhere, L = Le + a L, so L = Le / (1 - a). A path cut after D
// scattering events sums only Le (1 + a + ... + a^D) = Le (1 - a^(D+1)) / (1 - a): that
// is the bias of the bounce limit (3% at the report's D = 5 with a = 0.5). With cosine
// sampling and a constant albedo every path carries exactly this value (zero variance).
TEST(Integrators, WhiteFurnace) {
    Scene scene;
    const float a = 0.5f, le = 1.0f;
    Material m = Material::diffuse(glm::vec3(a));
    m.emission = glm::vec3(le);
    scene.add_sphere({{0, 0, 0}, 1.0f}, scene.add_material(m));
    scene.commit();
    Pinhole cam;
    cam.eye = {0.1f, -0.2f, 0.3f};
    cam.fov_degrees = 120.0f;
    cam.width = cam.height = 8;
    for (const int depth : {0, 1, 5, 200}) {
        const double expected = le * (1.0 - std::pow(double(a), depth + 1)) / (1.0 - a);
        BruteForcePathTracer brute({depth, false});
        PathTracer path({depth, false});
        for (Integrator* integrator :
             {static_cast<Integrator*>(&brute), static_cast<Integrator*>(&path)}) {
            const StatImage img = render_stats(scene, *integrator, cam, 4, 1);
            for (const auto& p : img.pixels)
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(p.mean()[c], expected, 1e-5 * expected);
        }
    }
    // Russian roulette keeps the expectation (now a random estimate): within 5 standard errors.
    PathTracer rr({1000, true, 3});
    const StatImage img = render_stats(scene, rr, cam, 256, 2);
    const auto all = region(img, 0, 0, cam.width, cam.height);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(all.se2[c], 0.0);
        EXPECT_LT(std::sqrt(all.se2[c]), 0.01);  // the test has power
        EXPECT_NEAR(all.mean[c], le / (1.0 - a), 5.0 * std::sqrt(all.se2[c]));
    }
    // Direct lighting never bounces off diffuse surfaces: emission only.
    DirectLighting direct;
    const StatImage d = render_stats(scene, direct, cam, 1, 1);
    EXPECT_NEAR(d.pixels[0].mean().x, le, 1e-6);
}

// Direct lighting against closed forms: a point light's I cos / d^2 * albedo / pi, and a
// sphere light seen head-on, whose irradiance is L pi sin^2(theta_max) = L pi r^2 / d^2.
TEST(Integrators, DirectLightingMatchesClosedForms) {
    const float albedo = 0.5f;
    {
        Scene scene;
        add_floor(scene, 10.0f, scene.add_material(Material::diffuse(glm::vec3(albedo))));
        scene.add_point_light({{0, 4, 0}, {100, 200, 300}});
        scene.commit();
        DirectLighting direct;
        Sampler sampler(0, 0, 0, 0);
        const glm::vec3 p(1.0f, 0.0f, 0.5f);
        const glm::vec3 l = direct.li(scene, Ray{p + glm::vec3(0, 2, 0), {0, -1, 0}}, sampler);
        const glm::vec3 to = glm::vec3(0, 4, 0) - p;
        const float d2 = glm::dot(to, to);
        const float cos_t = to.y / std::sqrt(d2);
        for (int c = 0; c < 3; ++c) {
            const float expected = albedo / kPi * 100.0f * float(c + 1) * cos_t / d2;
            EXPECT_NEAR(l[c], expected, 1e-5f * expected);
        }
        // A shadowing sphere in between: exactly black (hard shadow).
        scene.add_sphere({{0.5f, 2, 0.25f}, 0.5f},
                         scene.add_material(Material::diffuse(glm::vec3(1))));
        scene.commit();
        EXPECT_EQ(direct.li(scene, Ray{p + glm::vec3(0, 0.5f, 0), {0, -1, 0}}, sampler),
                  glm::vec3(0.0f));
    }
    {
        Scene scene;
        add_floor(scene, 10.0f, scene.add_material(Material::diffuse(glm::vec3(albedo))));
        const float r = 0.5f, h = 4.0f, radiance = 3.0f;
        scene.add_sphere_light({{{0, h, 0}, r}, glm::vec3(radiance)});
        scene.commit();
        DirectLighting direct;
        testing::PixelStats stats;
        for (std::uint32_t s = 0; s < 4096; ++s) {
            Sampler sampler(0, 0, s, 9);
            stats.add(direct.li(scene, Ray{{0, 1, 0}, {0, -1, 0}}, sampler));
        }
        const double expected = albedo / kPi * radiance * kPi * (r * r) / (h * h);
        const double se = std::sqrt(stats.variance().x / stats.n);
        EXPECT_NEAR(stats.mean().x, expected, 5.0 * se + 1e-6 * expected);
        EXPECT_LT(se, 0.01 * expected);
    }
}

// Mirrors and glass carry their tint; emitters seen through them count.
TEST(Integrators, EmissionSeenThroughMirrorIsTinted) {
    Scene scene;
    // Mirror floor facing +y; an emissive (non-light) quad above facing down.
    add_floor(scene, 10.0f, scene.add_material(Material::mirror(glm::vec3(0.5f, 0.25f, 1.0f))));
    const auto lamp = scene.add_material(Material::emissive(glm::vec3(2.0f)));
    TriangleMesh q;
    q.positions = {{-10, 5, -10}, {10, 5, -10}, {10, 5, 10}, {-10, 5, 10}};
    q.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(q, lamp);
    scene.commit();
    PathTracer path(PathTracerSettings{5, false});
    DirectLighting direct;
    BruteForcePathTracer brute(PathTracerSettings{5, false});
    for (Integrator* integ : {static_cast<Integrator*>(&path), static_cast<Integrator*>(&direct),
                              static_cast<Integrator*>(&brute)}) {
        Sampler sampler(1, 2, 3, 4);
        const glm::vec3 l =
            integ->li(scene, Ray{{0, 1, 0}, glm::normalize(glm::vec3(0.3f, -1, 0))}, sampler);
        EXPECT_NEAR(l.x, 1.0f, 1e-6f);
        EXPECT_NEAR(l.y, 0.5f, 1e-6f);
        EXPECT_NEAR(l.z, 2.0f, 1e-6f);
    }
}

// (b) PathTracer (light sampling) and BruteForcePathTracer (none) estimate the same image
// of the report's room with its sphere light: over the whole image and over 4 x 4 blocks,
// means agree within 5 standard errors of their difference.
TEST(Integrators, PathTracerAgreesWithBruteForceOnTheRoom) {
    Scene scene;
    add_room(scene);
    scene.add_sphere_light({{{-10, 20, 40}, 10}, glm::vec3(50.0f)});
    scene.commit();
    const Pinhole cam = room_camera(24);
    PathTracer path(PathTracerSettings{5, false});
    BruteForcePathTracer brute(PathTracerSettings{5, false});
    const StatImage a = render_stats(scene, path, cam, 48, 1);
    const StatImage b = render_stats(scene, brute, cam, 600, 2);
    EXPECT_EQ(path.nonfinite_count(), 0u);
    EXPECT_EQ(brute.nonfinite_count(), 0u);
    const auto whole_a = region(a, 0, 0, 24, 24), whole_b = region(b, 0, 0, 24, 24);
    expect_same(whole_a, whole_b, 5.0, 0.0, "whole image");
    // The comparison has power: the whole-image difference is resolved to a few percent.
    for (int c = 0; c < 3; ++c)
        EXPECT_LT(std::sqrt(whole_a.se2[c] + whole_b.se2[c]), 0.03 * whole_b.mean[c]) << c;
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx)
            expect_same(region(a, 6 * bx, 6 * by, 6 * bx + 6, 6 * by + 6),
                        region(b, 6 * bx, 6 * by, 6 * bx + 6, 6 * by + 6), 5.0, 0.0,
                        "block " + std::to_string(bx) + "," + std::to_string(by));
}

// (c) A point light and a sphere light of radius 1e-2 with the same power light the scene
// the same. Scene: a floor, a diffuse ball on it, the light above the camera on the ball's
// axis, so the ball hides its own shadow and no penumbra is visible (where a finite light
// would rightly differ). Allowed: 5 standard errors, plus 1e-5 relative for float rounding
// and the O((r/d)^2) ~ 1e-6 difference of a finite sphere.
TEST(Integrators, TinySphereLightMatchesPointLightOfTheSamePower) {
    const float power = 4000.0f;
    const glm::vec3 light_pos(0, 10, 0);
    auto build = [&](Scene& scene, bool sphere) {
        add_floor(scene, 20.0f, scene.add_material(Material::diffuse({0.8f, 0.6f, 0.4f})));
        scene.add_sphere({{0, 1, 0}, 1}, scene.add_material(Material::diffuse({0.3f, 0.7f, 0.5f})));
        if (sphere)
            scene.add_sphere_light(
                {{light_pos, 1e-2f}, SphereLight::radiance_for_power(power, 1e-2f)});
        else
            scene.add_point_light(PointLight::from_power(light_pos, power));
        scene.commit();
    };
    Scene point_scene, sphere_scene;
    build(point_scene, false);
    build(sphere_scene, true);
    Pinhole cam;
    cam.eye = {0, 6, 0};
    cam.forward = {0, -1, 0};
    cam.up = {0, 0, -1};
    cam.width = cam.height = 16;
    DirectLighting direct;
    PathTracer path({3, false});
    for (Integrator* integ : {static_cast<Integrator*>(&direct), static_cast<Integrator*>(&path)}) {
        const StatImage a = render_stats(point_scene, *integ, cam, 32, 5);
        const StatImage b = render_stats(sphere_scene, *integ, cam, 32, 6);
        for (int by = 0; by < 4; ++by)
            for (int bx = 0; bx < 4; ++bx)
                expect_same(region(a, 4 * bx, 4 * by, 4 * bx + 4, 4 * by + 4),
                            region(b, 4 * bx, 4 * by, 4 * bx + 4, 4 * by + 4), 5.0, 1e-5,
                            "block " + std::to_string(bx) + "," + std::to_string(by));
        // Power: the image mean is resolved to better than 1%.
        const auto whole = region(a, 0, 0, 16, 16);
        EXPECT_GT(whole.mean.x, 0.0);
        EXPECT_LT(std::sqrt(whole.se2.x), 0.01 * whole.mean.x);
    }
}

// (f) Scenes built to provoke NaN or Inf: grazing and tangent rays, total internal
// reflection, a camera inside a glass sphere, lights inside glass spheres, rays starting
// on surfaces or with degenerate directions. Every integrator must stay finite without
// needing its guard.
TEST(Integrators, FiniteOnHostileScenes) {
    Scene scene;
    const auto glass = scene.add_material(Material::dielectric(1.5f));
    const auto glass_nf = scene.add_material(Material::dielectric(2.4f, false));
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.9f)));
    const auto chrome = scene.add_material(Material::mirror());
    add_floor(scene, 10.0f, white);
    scene.add_sphere({{0, 2, 0}, 1.5f}, glass);  // holds a sphere light
    scene.add_sphere_light({{{0, 2, 0}, 0.4f}, glm::vec3(20.0f)});
    scene.add_sphere({{4, 2, 0}, 1.0f}, glass_nf);  // holds a point light
    scene.add_point_light({{4, 2, 0}, glm::vec3(50.0f)});
    scene.add_sphere({{-4, 2, 0}, 1.2f}, glass);  // holds the camera
    scene.add_sphere({{0, 2, -4}, 1.0f}, chrome);
    scene.add_sphere({{0, 0.5f, 4}, 0.5f}, white);                  // touches the floor
    scene.add_triangle({{-2, 0, 2}, {2, 0, 2}, {0, 3, 2}}, glass);  // a glass sheet, open mesh
    scene.add_sphere_light({{{3, 6, 3}, 0.5f}, glm::vec3(10.0f)});
    scene.commit();

    PathTracer path({8, false});
    PathTracer roulette({50, true, 2});
    DirectLighting direct;
    BruteForcePathTracer brute({8, false});
    AlbedoNormalIntegrator albedo(DebugView::Albedo), normal(DebugView::Normal);
    const std::vector<GuardedIntegrator*> integrators = {&path,  &roulette, &direct,
                                                         &brute, &albedo,   &normal};

    // Special rays: tangent to spheres, in the floor's plane, along a triangle edge, from a
    // surface point, inside glass at steep angles (TIR), zero and NaN directions.
    std::vector<Ray> rays = {
        {{-10, 3.5f, 0}, {1, 0, 0}},      // tangent to the top of the light's glass ball
        {{4, 3, -5}, {0, 0, 1}},          // tangent to the point light's ball
        {{-10, 0, 0.3f}, {1, 0, 0}},      // in the floor's plane
        {{-2, 0, 2}, {1, 0, 0}},          // along the glass sheet's edge
        {{0, 0, 0}, {0, 1, 0}},           // from the floor, up into the glass ball
        {{0, 3.5f, 0}, {0, -1, 0}},       // from the glass ball's surface, inward
        {{0, 2, 0}, {0.99f, 0.141f, 0}},  // from the light's centre
        {{4, 2, 0}, {0, 0.6f, 0.8f}},     // from the point light's position, in glass
        {{-4, 2, 0}, {0, 0, -1}},         // from inside the camera ball
        {{0, 1, 0}, {0, 0, 0}},           // zero direction
        {{0, 1, 0}, {NAN, 0, 1}},         // NaN direction
        {{0, 1, 0}, {INFINITY, 0, 1}},    // infinite direction
    };
    for (const Ray& ray : rays)
        for (GuardedIntegrator* integ : integrators)
            for (std::uint32_t s = 0; s < 64; ++s) {
                Sampler sampler(7, 7, s, 3);
                const glm::vec3 l = integ->li(scene, ray, sampler);
                ASSERT_TRUE(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z));
            }

    // Images from inside the glass ball (steep angles: TIR) and from outside.
    Pinhole inside;
    inside.eye = {-4, 2, 0};
    inside.forward = {1, 0, 0};
    inside.fov_degrees = 150.0f;
    inside.width = inside.height = 12;
    Pinhole outside;
    outside.eye = {0, 3, 9};
    outside.width = outside.height = 12;
    for (const Pinhole& cam : {inside, outside})
        for (GuardedIntegrator* integ : integrators) {
            const StatImage img = render_stats(scene, *integ, cam, 8, 11);
            for (const auto& p : img.pixels) {
                const glm::dvec3 m = p.mean();
                ASSERT_TRUE(std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.z));
                ASSERT_GE(std::min({m.x, m.y, m.z}), 0.0);
            }
        }
    for (GuardedIntegrator* integ : integrators) EXPECT_EQ(integ->nonfinite_count(), 0u);
    // Something was lit: the light inside glass reaches the floor through it.
    const StatImage img = render_stats(scene, path, outside, 8, 12);
    EXPECT_GT(region(img, 0, 0, 12, 12).mean.x, 0.0);
}

// (g) Degenerate geometry, through the real renderer (jittered camera, several threads):
// a mesh whose vertex normals are all zero, zero-area and sliver triangles, spheres and a
// sphere light of radius 1e-6 and 1e-20 (radius 0 is refused by add_sphere), a mirror and a
// glass ball seen at grazing angles from a camera in the floor's plane, and a glass ball
// showing total internal reflection. Every pixel must be finite, with no sample dropped
// by the renderer or replaced by the integrators' guard (a debug build would assert).
TEST(Integrators, FiniteOnDegenerateGeometry) {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.8f)));
    const auto chrome = scene.add_material(Material::mirror());
    const auto glass = scene.add_material(Material::dielectric(1.8f));
    const auto lamp = scene.add_material(Material::emissive(glm::vec3(5.0f)));
    add_floor(scene, 20.0f, white);
    TriangleMesh flat;  // a tent with all-zero vertex normals, plus degenerate triangles
    flat.positions = {{-3, 0, -3},  {3, 0, -3}, {0, 3, -2},   {0, 0, 0},
                      {1, 1, 1},    {2, 2, 2},  {5, 0.5f, 0}, {5, 0.5f, 0},
                      {5, 0.5f, 0}, {-4, 0, 1}, {4, 0, 1},    {0, 1e-20f, 1}};
    flat.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}};
    flat.normals.assign(flat.positions.size(), glm::vec3(0.0f));
    flat.uvs.assign(flat.positions.size(), glm::vec2(0.5f));
    scene.add_mesh(flat, white);
    scene.add_mesh(flat, glass);  // the same shape in glass: flat normals, open mesh
    scene.add_sphere({{1, 1, 3}, 1e-6f}, white);
    scene.add_sphere({{-1, 1, 3}, 1e-20f}, chrome);
    scene.add_sphere({{3, 1, 1}, 1.0f}, chrome);
    scene.add_sphere({{-3, 1, 1}, 1.0f}, glass);
    scene.add_sphere({{0, 6, 0}, 0.5f}, lamp);  // an emissive sphere that is not a light
    scene.add_sphere_light({{{2, 4, 2}, 1e-20f}, glm::vec3(1.0f)});
    scene.add_sphere_light({{{-2, 4, 2}, 1e-6f}, glm::vec3(1e6f)});
    scene.add_sphere_light({{{0, 8, 4}, 1.0f}, glm::vec3(4.0f)});
    scene.add_point_light({{0, 5, 5}, glm::vec3(50.0f)});
    scene.add_point_light({{0, 0, 1}, glm::vec3(50.0f)});  // exactly on a degenerate triangle
    scene.commit();

    PathTracer path({6, false});
    PathTracer roulette({30, true, 1});
    DirectLighting direct;
    BruteForcePathTracer brute({6, false});
    AlbedoNormalIntegrator normal(DebugView::Normal);
    const std::vector<GuardedIntegrator*> integrators = {&path, &roulette, &direct, &brute,
                                                         &normal};
    std::vector<CameraSettings> cameras(3);
    cameras[0].position = {0, 3, 12};  // overview
    cameras[0].look_at = {0, 1, 0};
    cameras[1].position = {-12, 0, 1};  // in the floor's plane: grazing everything
    cameras[1].look_at = {0, 0, 1};
    cameras[2].position = {-3, 1, 1};  // inside the glass ball, looking at grazing angles
    cameras[2].look_at = {0, 1, 1};
    cameras[2].vertical_fov_degrees = 170.0f;
    for (CameraSettings& cs : cameras) {
        cs.width = cs.height = 12;
        cs.pixel_jitter = PixelJitter::Gaussian;
        cs.lens = LensModel::Disk;
        cs.lens_radius = 0.05f;
        cs.focal_distance = 10.0f;
    }
    RenderSettings settings;
    settings.samples_per_pixel = 6;
    settings.threads = 2;
    settings.tile_size = 5;
    settings.progress = nullptr;
    for (const CameraSettings& cs : cameras)
        for (GuardedIntegrator* integ : integrators) {
            RenderStats stats;
            const Image image = render(scene, Camera(cs), *integ, settings, &stats);
            EXPECT_EQ(stats.nonfinite_samples, 0u);
            for (const glm::vec3& p : image.pixels) {
                ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
                ASSERT_GE(std::min({p.x, p.y, p.z}), 0.0f);
            }
        }
    for (GuardedIntegrator* integ : integrators) EXPECT_EQ(integ->nonfinite_count(), 0u);
}

#ifdef NDEBUG
// The guard itself (release builds only: a debug build asserts instead): emission so large
// that the path's sum overflows becomes 0 and is counted.
TEST(Integrators, GuardCountsNonFiniteSamples) {
    Scene scene;
    Material m = Material::diffuse(glm::vec3(1.0f));
    m.emission = glm::vec3(3e38f);
    scene.add_sphere({{0, 0, 0}, 1.0f}, scene.add_material(m));
    scene.commit();
    PathTracer path(PathTracerSettings{5, false});
    Sampler sampler(0, 0, 0, 0);
    EXPECT_EQ(path.li(scene, Ray{{0, 0, 0}, {0, 0, 1}}, sampler), glm::vec3(0.0f));
    EXPECT_EQ(path.nonfinite_count(), 1u);
}
#endif

}  // namespace
}  // namespace librt
