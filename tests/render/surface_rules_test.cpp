// The surface rules of glTF as a path tracer draws them (issue 42, "spec-correct
// surfaces"): a one-sided surface's back is culled for camera rays (invisible, not black),
// alphaMode BLEND is partial coverage (stochastic opacity: rays pass with probability
// 1 - alpha, camera, bounce and shadow rays alike), and a normal map bent away from the
// viewer loses no light (a normal-mapped mirror sphere in a white furnace is white).

#include "box_scene_test_util.h"
#include "integrator_test_util.h"

#include <librt/film/camera.h>
#include <librt/integrator/bdpt.h>
#include <librt/integrator/integrators.h>
#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/material/normal_map.h>
#include <librt/render/renderer.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace librt {
namespace {

constexpr float kPi = 3.14159265f;

// The square [-h, h]^2 in the plane z, facing +z (up) or -z.
TriangleMesh square(float z, float h, bool up = true) {
    TriangleMesh m;
    m.positions = {{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    if (up)
        m.triangles = {{0, 1, 2}, {0, 2, 3}};
    else
        m.triangles = {{0, 2, 1}, {0, 3, 2}};
    return m;
}

// A camera-like ray from z = 3 straight down at a random point of [-0.5, 0.5]^2, slightly
// tilted: every sample's ray differs, as the renderer's jittered camera rays do.
Ray random_down_ray(Pcg32& rng) {
    const glm::vec3 o(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 3.0f);
    const glm::vec3 d(0.02f * (rng.next_float() - 0.5f), 0.02f * (rng.next_float() - 0.5f), -1.0f);
    return Ray(o, glm::normalize(d));
}

// Mean and standard error of li over n random downward rays.
struct Estimate {
    double mean = 0.0;
    double se = 0.0;
};

Estimate estimate(const Scene& scene, const Integrator& integrator, int n, std::uint64_t seed,
                  const Ray* fixed = nullptr) {
    Pcg32 rng(seed, 11);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const Ray ray = fixed != nullptr ? *fixed : random_down_ray(rng);
        Sampler sampler(std::uint32_t(i), 0, 0, seed);
        const double v = integrator.li(scene, ray, sampler).x;
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

// --- Back-face culling (glTF doubleSided false) ---

// A one-sided black quad at z = 0 over a white emitting wall at z = -1, seen from z = 3.
Scene quad_over_wall(bool quad_faces_camera) {
    Scene scene;
    Material quad = Material::diffuse(glm::vec3(0.0f));
    quad.double_sided = false;
    (void)scene.add_mesh(square(0.0f, 1.0f, quad_faces_camera), scene.add_material(quad));
    (void)scene.add_mesh(square(-1.0f, 3.0f),
                         scene.add_material(Material::emissive(glm::vec3(1.0f))));
    scene.commit();
    return scene;
}

TEST(BackFaceCulling, OneSidedQuadSeenFromBehindIsInvisibleToCameraRays) {
    const Scene back = quad_over_wall(false);
    const Scene front = quad_over_wall(true);
    ASSERT_TRUE(back.camera_may_pass());
    PathTracer path({4});
    BruteForcePathTracer brute({4});
    BidirectionalPathTracer bdpt(BidirectionalSettings{4});
    bdpt.preprocess(back);
    // Its back: the wall behind it, exactly (the wall is a pure emitter: nothing else adds).
    for (const Integrator* integrator :
         {static_cast<const Integrator*>(&path), static_cast<const Integrator*>(&brute),
          static_cast<const Integrator*>(&bdpt)}) {
        const Estimate e = estimate(back, *integrator, 200, 1);
        EXPECT_NEAR(e.mean, 1.0, 1e-6) << "the quad's back is culled";
    }
    // Its front: the black quad, hiding the wall.
    EXPECT_NEAR(estimate(front, path, 200, 2).mean, 0.0, 1e-6);
    // Every other ray still meets the back, a black absorber: it casts its shadow.
    const Ray down({0.1f, 0.2f, 3.0f}, {0, 0, -1});
    Hit hit;
    ASSERT_TRUE(back.intersect_for_shading(down, hit));
    EXPECT_FLOAT_EQ(hit.point.z, 0.0f);
    EXPECT_TRUE(back.camera_passes(hit, down.direction));
    ShadedMaterial scratch;
    EXPECT_EQ(lobes(back.shade(hit, down.direction, scratch)), BsdfLobe::None);
    Ray shadow = down;
    shadow.t_max = 3.5f;
    EXPECT_TRUE(back.occluded(shadow));
    // A double-sided copy is seen from both sides.
    Scene two;
    (void)two.add_mesh(square(0.0f, 1.0f, false),
                       two.add_material(Material::diffuse(glm::vec3(0.0f))));
    two.commit();
    EXPECT_FALSE(two.camera_may_pass());
    ASSERT_TRUE(two.intersect_for_shading(down, hit));
    EXPECT_FALSE(two.camera_passes(hit, down.direction));
}

// The joins of light paths to the lens (the bidirectional tracer's t = 1 strategies) pass
// what camera rays pass: a one-sided pane in front of the lit box, its back to the camera,
// must leave the splatted image equal to the brute-force path tracer's (which sees the box
// through it). A join stopped by the culled back would darken the blocks behind the pane.
TEST(BackFaceCulling, LightPathJoinsToTheLensPassCulledBacks) {
    Scene scene;
    testing::build_box(scene, true, false, false);
    Material pane = Material::diffuse(glm::vec3(0.8f));
    pane.double_sided = false;
    // Facing -z (into the box), between it and the camera at z = 3.4.
    testing::add_quad(scene, {-0.6f, 0.3f, 1.5f}, {0.0f, 1.2f, 0.0f}, {1.2f, 0.0f, 0.0f},
                      scene.add_material(pane));
    scene.commit();
    BidirectionalSettings bd;
    bd.max_depth = 3;
    BidirectionalPathTracer bdpt(bd);
    bdpt.preprocess(scene);
    ASSERT_TRUE(bdpt.splats());
    PathTracerSettings pt;
    pt.max_depth = 3;
    pt.russian_roulette = false;
    BruteForcePathTracer brute(pt);
    testing::expect_splatting_agrees(scene, Camera(testing::box_camera_settings(16)), bdpt, 16,
                                     brute, 256, 31, "one-sided pane before the box");
}

// --- Partial coverage (glTF alphaMode BLEND) ---

Material blend(float alpha) {
    Material m = Material::diffuse(glm::vec3(0.0f));
    m.alpha = alpha;
    m.alpha_blend = true;
    return m;
}

TEST(StochasticAlpha, BlendQuadOfAlpha03ShowsSevenTenthsOfTheWallBehind) {
    Scene scene;
    const std::uint32_t quad = scene.add_mesh(square(0.0f, 1.0f), scene.add_material(blend(0.3f)));
    const std::uint32_t wall = scene.add_mesh(
        square(-1.0f, 3.0f), scene.add_material(Material::emissive(glm::vec3(1.0f))));
    scene.commit();
    // Each ray sees 1 or 0: a Bernoulli mean of variance 0.21 / n, within 5 sigma.
    const int n = 40000;
    const double tol = 5.0 * std::sqrt(0.21 / n);
    PathTracer path({4});
    BruteForcePathTracer brute({4});
    EXPECT_NEAR(estimate(scene, path, n, 3).mean, 0.7, tol) << "path tracer";
    EXPECT_NEAR(estimate(scene, brute, n, 4).mean, 0.7, tol) << "brute force";
    // The queries themselves: closest hits on the wall, shadow rays (ending before the
    // wall) unblocked, 0.7 of the time; the same ray always decides the same way.
    Pcg32 rng(5, 1);
    int through = 0, unblocked = 0;
    for (int i = 0; i < n; ++i) {
        const Ray ray = random_down_ray(rng);
        Hit a, b;
        ASSERT_TRUE(scene.intersect_for_shading(ray, a));
        ASSERT_TRUE(scene.intersect(ray, b));
        ASSERT_EQ(a.object_id, b.object_id);
        ASSERT_TRUE(a.object_id == quad || a.object_id == wall);
        through += a.object_id == wall;
        Ray shadow = ray;
        shadow.t_max = 3.5f;
        const bool blocked = scene.occluded(shadow);
        // A shadow ray is the same ray to the same surfaces: the same decision.
        ASSERT_EQ(blocked, a.object_id == quad);
        unblocked += !blocked;
    }
    EXPECT_NEAR(double(through) / n, 0.7, tol);
    EXPECT_EQ(through, unblocked);
    // Two layers decide independently: 0.7 x 0.5 of the wall through alpha 0.3 over 0.5.
    Scene layers;
    (void)layers.add_mesh(square(0.0f, 1.0f), layers.add_material(blend(0.3f)));
    (void)layers.add_mesh(square(-0.5f, 1.5f), layers.add_material(blend(0.5f)));
    (void)layers.add_mesh(square(-1.0f, 3.0f),
                          layers.add_material(Material::emissive(glm::vec3(1.0f))));
    layers.commit();
    EXPECT_NEAR(estimate(layers, path, n, 6).mean, 0.35, 5.0 * std::sqrt(0.35 * 0.65 / n));
}

// A white floor lit by an emitting square 2 above it, with (or without) a BLEND layer of
// alpha 0.3 between them; seen from just above the floor, under the layer.
Scene lit_floor(bool layer) {
    Scene scene;
    (void)scene.add_mesh(square(0.0f, 10.0f),
                         scene.add_material(Material::diffuse(glm::vec3(0.8f))));
    Material light = Material::emissive(glm::vec3(1.0f));
    light.double_sided = false;
    (void)scene.add_mesh(square(2.0f, 1.0f, false), scene.add_material(light));
    if (layer) (void)scene.add_mesh(square(1.0f, 10.0f), scene.add_material(blend(0.3f)));
    scene.commit();
    return scene;
}

// The floor's light reaches it through the layer 0.7 of the time, along shadow rays (the
// path tracer's light sample alone at its last vertex) and along bounce rays (the brute
// force tracer, which samples no light): each reads 0.7 of the same floor without it.
TEST(StochasticAlpha, ShadowAndBounceRaysPassABlendLayerWithProbabilityOneMinusAlpha) {
    const Scene open = lit_floor(false), covered = lit_floor(true);
    const Ray view({0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, -1.0f});
    PathTracer shadow_rays({1});  // one vertex, light sample alone (no MIS at the last one)
    BruteForcePathTracer bounce_rays({1});
    const int n = 200000;
    for (const Integrator* integrator : {static_cast<const Integrator*>(&shadow_rays),
                                         static_cast<const Integrator*>(&bounce_rays)}) {
        const Estimate a = estimate(open, *integrator, n, 7, &view);
        const Estimate b = estimate(covered, *integrator, n, 8, &view);
        ASSERT_GT(a.mean, 0.05);
        EXPECT_LT(b.se, 0.01 * b.mean) << "the test has power";
        EXPECT_NEAR(b.mean, 0.7 * a.mean, 5.0 * std::sqrt(b.se * b.se + 0.49 * a.se * a.se));
    }
}

// The decision is a hash of the ray and the hit: a render is the same bits for any number
// of threads and tiles.
TEST(StochasticAlpha, RendersAreTheSameForAnyThreadCount) {
    Scene scene;
    testing::build_box(scene, true, false, false);
    testing::add_quad(scene, {-0.6f, 0.3f, 0.5f}, {1.2f, 0.0f, 0.0f}, {0.0f, 1.2f, 0.0f},
                      scene.add_material(blend(0.5f)));
    scene.commit();
    const Camera camera(testing::box_camera_settings(24));
    PathTracer path({4});
    RenderSettings rs;
    rs.samples_per_pixel = 4;
    rs.threads = 1;
    rs.tile_size = 16;
    const Image one = render(scene, camera, path, rs);
    rs.threads = 2;
    rs.tile_size = 5;
    const Image two = render(scene, camera, path, rs);
    ASSERT_EQ(one.width, two.width);
    for (int y = 0; y < one.height; ++y)
        for (int x = 0; x < one.width; ++x) ASSERT_EQ(one.at(x, y), two.at(x, y)) << x << "," << y;
}

// --- Normal maps that lose no light ---

// A UV sphere mesh of radius 1 (u the azimuth, v from the south pole up), normals outward.
TriangleMesh uv_sphere(int rings, int segments) {
    TriangleMesh m;
    for (int i = 0; i <= rings; ++i) {
        const float theta = kPi * float(i) / float(rings);  // from the north pole
        for (int j = 0; j <= segments; ++j) {
            const float phi = 2.0f * kPi * float(j) / float(segments);
            const glm::vec3 p(std::sin(theta) * std::cos(phi), std::cos(theta),
                              -std::sin(theta) * std::sin(phi));
            m.positions.push_back(p);
            m.normals.push_back(p);
            m.uvs.push_back({float(j) / float(segments), 1.0f - float(i) / float(rings)});
        }
    }
    const auto at = [&](int i, int j) { return std::uint32_t(i * (segments + 1) + j); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            // Counter-clockwise seen from outside.
            if (i > 0) m.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
            if (i + 1 < rings)
                m.triangles.push_back({at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
        }
    return m;
}

// A mirror or a smooth white metal (F = 1), normal-mapped by one texel bent 60 degrees along
// the tangent, inside a uniform emitter of radiance 1: every reflected ray leaves the convex
// sphere and meets the emitter, so every pixel is 1 (the mirror exactly; the GGX metal of
// roughness 0 on average, up to its lobe's tail). A mapped normal turned away from the viewer made
// rims and whole bands black: no reflection, or one below the surface, ended the path.
TEST(NormalMapEnergy, NormalMappedMetalSphereInAWhiteFurnaceIsWhite) {
    const float bend = kPi / 3.0f;
    for (const bool mirror : {true, false}) {
        Scene scene;
        ImageTexture texel(
            1, 1, {glm::vec3(0.5f + 0.5f * std::sin(bend), 0.5f, 0.5f + 0.5f * std::cos(bend))});
        texel.set_sampling({TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest});
        Material m =
            mirror ? Material::mirror() : Material::metallic_roughness(glm::vec3(1.0f), 1.0f, 0.0f);
        m.normal_texture.texture = scene.add_texture(std::move(texel));
        (void)scene.add_mesh(uv_sphere(48, 96), scene.add_material(m));
        scene.add_sphere({{0, 0, 0}, 50.0f},
                         scene.add_material(Material::emissive(glm::vec3(1.0f))));
        scene.commit();
        testing::Pinhole cam;
        cam.eye = {0.0f, 0.0f, 4.0f};
        cam.fov_degrees = 32.0f;
        cam.width = cam.height = 24;
        PathTracer path({8});
        const testing::StatImage img = testing::render_stats(scene, path, cam, 4, 9);
        int on_sphere = 0;
        double sphere_sum = 0.0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const Ray ray = cam.ray(x, y);
                Hit hit;
                ASSERT_TRUE(scene.intersect(ray, hit));
                const double v = img.at(x, y).mean().x;
                if (hit.t < 10.0f) {
                    ++on_sphere;
                    sphere_sum += v;
                }
                // The mirror loses nothing, pixel by pixel.
                if (mirror) EXPECT_NEAR(v, 1.0, 1e-5) << "mirror pixel " << x << "," << y;
            }
        // The GGX metal's lobe (alpha 10^-3) has a long tail: about the adapted normal, which
        // mirrors the viewer 0.01 above the surface, a few of its samples still go below it
        // (0.3 % here; without the adaptation, bands of pixels lose everything).
        if (!mirror) EXPECT_GT(sphere_sum / on_sphere, 0.99) << "metal";
        EXPECT_GT(on_sphere, 150) << "the sphere fills the image's middle";
    }
}

// adapt_shading_normal keeps a normal whose mirror direction is above the surface, and
// otherwise returns one about which the viewer's mirror direction is just above it.
TEST(NormalMapEnergy, AdaptedNormalMirrorsTheViewerAboveTheSurface) {
    const glm::vec3 g(0, 0, 1);
    const glm::vec3 kept = glm::normalize(glm::vec3(0.2f, 0.0f, 1.0f));
    const glm::vec3 wo_up(0, 0, 1);
    EXPECT_EQ(adapt_shading_normal(kept, g, wo_up), kept);
    Pcg32 rng(3, 9);
    int adapted = 0;
    for (int i = 0; i < 2000; ++i) {
        // A normal up to 80 degrees off g, a viewer anywhere above the surface, either side
        // of the primitive (the hit gives n and g on the primitive's side).
        const float a = 1.4f * rng.next_float(), b = 2.0f * kPi * rng.next_float();
        const glm::vec3 n(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a));
        const float c = 0.02f + 0.98f * rng.next_float(), d = 2.0f * kPi * rng.next_float();
        const float s = std::sqrt(1.0f - c * c);
        const float side = i % 2 == 0 ? 1.0f : -1.0f;
        const glm::vec3 wo = side * glm::vec3(s * std::cos(d), s * std::sin(d), c);
        const glm::vec3 out = adapt_shading_normal(n, g, wo);
        ASSERT_NEAR(glm::length(out), 1.0f, 1e-5f);
        ASSERT_GT(glm::dot(out, g), 0.0f) << "on the side it was given";
        const glm::vec3 ns = side * out;
        const glm::vec3 r = 2.0f * glm::dot(wo, ns) * ns - wo;
        EXPECT_GE(glm::dot(r, side * g), kMinMirrorCosine - 1e-4f) << i;
        EXPECT_GT(glm::dot(wo, ns), 0.0f) << i;
        adapted += out != n;
    }
    EXPECT_GT(adapted, 200) << "bent normals that needed it";
}

}  // namespace
}  // namespace librt
