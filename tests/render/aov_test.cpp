// The AOV layers against geometry whose answers are known in closed form: depth is the
// planar depth of a plane (its distance from the lens plane along the view axis, what
// compositors read as Z), the normal that plane's, and the albedo the first non-specular
// surface's, tinted by the mirrors and glass on the way (aov_albedo_test.cpp: every kind).

#include "axis_camera.h"

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/geometry/procedural.h>
#include <librt/geometry/ray.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace librt;

namespace {

constexpr std::uint32_t kSpp = 3;

using librt::testing::axis_camera;

// A 100 x 100 slab between z0 and z1 (z0 < z1), facing the z axis with both big faces.
TriangleMesh slab(float z0, float z1) { return make_box({-50.0f, -50.0f, z0}, {50.0f, 50.0f, z1}); }

ImageLayers render_layers(const Scene& scene, const CameraSettings& cs) {
    const Camera camera(cs);
    PathTracer integrator(PathTracerSettings{3, false});
    integrator.preprocess(scene);
    Film film(cs.width, cs.height, true);
    (void)render_block(scene, camera, integrator, film, {0, 0, cs.width, cs.height, 0, kSpp},
                       BlockSettings{});
    return resolve_layers(film);
}

// Distance from the camera to the plane z = plane along the ray of pixel (x, y).
float distance_to_plane(const Camera& camera, int x, int y, float plane) {
    Sampler sampler(0, 0, 0, 0);
    const Ray ray = camera.generate_ray(x, y, sampler);
    const glm::vec3 d = glm::normalize(ray.direction);
    return (plane - ray.origin.z) / d.z;
}

}  // namespace

TEST(Aov, DiffuseWallGivesItsAlbedoNormalAndPlanarDepth) {
    Scene scene;
    const glm::vec3 albedo(0.25f, 0.5f, 0.75f);
    (void)scene.add_mesh(slab(-6.0f, -5.0f), scene.add_material(Material::diffuse(albedo)));
    scene.commit();
    const CameraSettings cs = axis_camera();
    const ImageLayers layers = render_layers(scene, cs);
    for (int y = 0; y < cs.height; ++y) {
        for (int x = 0; x < cs.width; ++x) {
            EXPECT_EQ(layers.albedo.at(x, y), albedo);
            EXPECT_EQ(layers.normal.at(x, y), glm::vec3(0.0f, 0.0f, 1.0f));
            EXPECT_NEAR(layers.depth[static_cast<std::size_t>(y * cs.width + x)], 5.0f, 1e-5f);
            EXPECT_EQ(layers.sample_count[static_cast<std::size_t>(y * cs.width + x)], 3.0f);
        }
    }
}

// Depth stops at the mirror (the first hit); albedo and normal come from the wall the
// mirror shows, behind the camera, the albedo tinted by the mirror.
TEST(Aov, MirrorsAreFollowedToTheFirstDiffuseHit) {
    Scene scene;
    (void)scene.add_mesh(slab(-6.0f, -5.0f), scene.add_material(Material::mirror(glm::vec3(0.5f))));
    (void)scene.add_mesh(slab(5.0f, 6.0f),
                         scene.add_material(Material::diffuse({0.8f, 0.6f, 0.4f})));
    scene.commit();
    const CameraSettings cs = axis_camera();
    const ImageLayers layers = render_layers(scene, cs);
    for (int y = 0; y < cs.height; ++y) {
        for (int x = 0; x < cs.width; ++x) {
            const glm::vec3 a = layers.albedo.at(x, y);
            EXPECT_NEAR(a.x, 0.4f, 1e-6f);
            EXPECT_NEAR(a.y, 0.3f, 1e-6f);
            EXPECT_NEAR(a.z, 0.2f, 1e-6f);
            EXPECT_EQ(layers.normal.at(x, y), glm::vec3(0.0f, 0.0f, -1.0f));
            EXPECT_NEAR(layers.depth[static_cast<std::size_t>(y * cs.width + x)], 5.0f, 1e-5f);
        }
    }
}

// Glass that always refracts (no Fresnel): through both faces of a slab to the wall, the
// albedo tinted once per face.
TEST(Aov, GlassIsFollowedThroughToTheWallBehind) {
    Scene scene;
    (void)scene.add_mesh(slab(-3.0f, -2.0f),
                         scene.add_material(Material::dielectric(1.5f, false, glm::vec3(0.9f))));
    const glm::vec3 albedo(0.2f, 0.4f, 0.8f);
    (void)scene.add_mesh(slab(-8.0f, -5.0f), scene.add_material(Material::diffuse(albedo)));
    scene.commit();
    const CameraSettings cs = axis_camera();
    const ImageLayers layers = render_layers(scene, cs);
    const glm::vec3 expected_albedo = 0.81f * albedo;
    for (int y = 0; y < cs.height; ++y) {
        for (int x = 0; x < cs.width; ++x) {
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(layers.albedo.at(x, y)[c], expected_albedo[c], 1e-6f);
            EXPECT_NEAR(layers.normal.at(x, y).z, 1.0f, 1e-6f);
            EXPECT_NEAR(layers.depth[static_cast<std::size_t>(y * cs.width + x)], 2.0f, 1e-5f);
        }
    }
}

// With Fresnel, glass reflects with probability F: the albedo is the F-weighted mean of
// what reflection (a red wall behind the camera) and refraction (a blue wall behind the
// glass) show. At normal incidence Schlick's F = R0 = ((1 - 1.5) / (1 + 1.5))^2 = 0.04 at
// either face, so a path ends on the red wall with probability
// R0 + (1 - R0)^2 R0 (1 + R0^2 + R0^4 + ...) = R0 + (1 - R0)^2 R0 / (1 - R0^2)
// (reflected at the front face, or refracted in, reflected at the back face 2k + 1 times
// in all, and refracted out through the front): a Bernoulli mean, tested to 4 sigma.
TEST(Aov, FresnelGlassMixesReflectionAndRefraction) {
    Scene scene;
    (void)scene.add_mesh(slab(-3.0f, -2.0f), scene.add_material(Material::dielectric(1.5f)));
    (void)scene.add_mesh(slab(-8.0f, -5.0f), scene.add_material(Material::diffuse({0, 0, 1})));
    (void)scene.add_mesh(slab(5.0f, 6.0f), scene.add_material(Material::diffuse({1, 0, 0})));
    scene.commit();
    CameraSettings cs = axis_camera(1, 1);
    cs.vertical_fov_degrees = 1.0f;  // close to normal incidence
    const Camera camera(cs);
    PathTracer integrator(PathTracerSettings{1, false});
    Film film(1, 1, true);
    const std::uint32_t n = 20000;
    BlockSettings independent;  // the binomial standard error below
    independent.sampler = SamplerKind::Independent;
    (void)render_block(scene, camera, integrator, film, {0, 0, 1, 1, 0, n}, independent);
    const ImageLayers layers = resolve_layers(film);
    const double r0 = 0.04;
    const double p = r0 + (1.0 - r0) * (1.0 - r0) * r0 / (1.0 - r0 * r0);
    const double sigma = std::sqrt(p * (1.0 - p) / n);
    EXPECT_NEAR(layers.albedo.at(0, 0).x, p, 4.0 * sigma);
    EXPECT_NEAR(layers.albedo.at(0, 0).x + layers.albedo.at(0, 0).z, 1.0, 1e-5);
}

TEST(Aov, MissesAndEmittersAndEndlessMirrors) {
    // Nothing to hit: zero albedo and normal, infinite depth.
    Scene empty;
    empty.commit();
    const ImageLayers none = render_layers(empty, axis_camera(2, 2));
    EXPECT_EQ(none.albedo.at(1, 1), glm::vec3(0.0f));
    EXPECT_EQ(none.normal.at(1, 1), glm::vec3(0.0f));
    EXPECT_TRUE(std::isinf(none.depth[3]));

    // An emitter reflects nothing.
    Scene light;
    (void)light.add_mesh(slab(-6.0f, -5.0f),
                         light.add_material(Material::emissive(glm::vec3(3.0f))));
    light.commit();
    const ImageLayers lit = render_layers(light, axis_camera(2, 2));
    EXPECT_EQ(lit.albedo.at(0, 0), glm::vec3(0.0f));
    EXPECT_GT(lit.beauty.at(0, 0).x, 0.0f);

    // Two facing mirrors and a ray along their axis: it never reaches a diffuse surface.
    Scene hall;
    const auto mirror = hall.add_material(Material::mirror());
    (void)hall.add_mesh(slab(-6.0f, -5.0f), mirror);
    (void)hall.add_mesh(slab(5.0f, 6.0f), mirror);
    hall.commit();
    const ImageLayers endless = render_layers(hall, axis_camera(1, 1));
    EXPECT_EQ(endless.albedo.at(0, 0), glm::vec3(0.0f));
    EXPECT_EQ(endless.normal.at(0, 0), glm::vec3(0.0f));
    EXPECT_NEAR(endless.depth[0], 5.0f, 1e-5f);
}

// Z is planar depth, as Blender and Nuke read it: a wall facing the camera at depth 5 gives
// 5 in every pixel, corners included, while the distance along the ray (what Z held before
// issue 38) grows toward the corners.
TEST(Aov, DepthIsPlanarNotTheRayLength) {
    Scene scene;
    (void)scene.add_mesh(slab(-6.0f, -5.0f),
                         scene.add_material(Material::diffuse({0.5f, 0.5f, 0.5f})));
    scene.commit();
    const CameraSettings cs = axis_camera(9, 7);
    const ImageLayers layers = render_layers(scene, cs);
    const Camera camera(cs);
    for (int y = 0; y < cs.height; ++y)
        for (int x = 0; x < cs.width; ++x)
            EXPECT_NEAR(layers.depth[static_cast<std::size_t>(y * cs.width + x)], 5.0f, 1e-5f)
                << "pixel " << x << ", " << y;
    // The test tells the two apart: the corner ray is over 10 % longer than 5, the centre
    // one is 5.
    EXPECT_GT(distance_to_plane(camera, 0, 0, -5.0f), 5.5f);
    EXPECT_GT(distance_to_plane(camera, cs.width - 1, cs.height - 1, -5.0f), 5.5f);
    EXPECT_NEAR(distance_to_plane(camera, 4, 3, -5.0f), 5.0f, 1e-5f);
}

// With a thin lens every ray starts on the lens plane, off the camera's position, and a
// tilted camera's view axis is no world axis: a plane perpendicular to that axis at depth
// 7 from the lens still gives Z = 7 everywhere (pixel jitter and lens samples included).
TEST(Aov, DepthIsPlanarForATiltedThinLensCamera) {
    CameraSettings cs;
    cs.position = {1.0f, 2.0f, 3.0f};
    cs.look_at = {-2.0f, 0.5f, -4.0f};
    cs.width = 7;
    cs.height = 5;
    cs.vertical_fov_degrees = 70.0f;
    cs.pixel_jitter = PixelJitter::Gaussian;
    cs.lens = LensModel::Disk;
    cs.lens_radius = 0.5f;
    cs.focal_distance = 4.0f;
    const Camera camera(cs);
    constexpr float kDepth = 7.0f;
    // A 200 x 200 quad centred on the axis at depth 7, spanned by the camera's own axes.
    const glm::vec3 centre = cs.position + kDepth * camera.forward();
    TriangleMesh wall = make_quad(centre - 100.0f * camera.right() - 100.0f * camera.true_up(),
                                  200.0f * camera.right(), 200.0f * camera.true_up());
    Scene scene;
    (void)scene.add_mesh(std::move(wall), scene.add_material(Material::diffuse(glm::vec3(0.5f))));
    scene.commit();
    const ImageLayers layers = render_layers(scene, cs);
    for (int y = 0; y < cs.height; ++y)
        for (int x = 0; x < cs.width; ++x)
            EXPECT_NEAR(layers.depth[static_cast<std::size_t>(y * cs.width + x)], kDepth, 1e-4f)
                << "pixel " << x << ", " << y;
}
