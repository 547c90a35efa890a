// PathTracer's caustic light paths (CausticPathSettings): a point light's image in a mirror
// ceiling against its closed form (the path tracer alone cannot render it at all), the
// split path tracer against brute force in a box with a panel, a glass pane and a glossy
// metal, and what must not change: li() alone, bad settings, thread and tile counts.

#include "integrator/caustic_paths.h"

#include "box_scene_test_util.h"

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/light/point_light.h>
#include <librt/light/quad_light.h>
#include <librt/light/sphere_light.h>
#include <librt/material/material.h>
#include <librt/render/renderer.h>
#include <librt/sampling/sampler.h>
#include <librt/sampling/warp.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace librt {
namespace {

using testing::add_quad;
using testing::block_means;
using testing::box_camera_settings;
using testing::build_box;
using testing::build_box_under_sky;
using testing::expect_blocks_agree;
using testing::spread;

PathTracerSettings caustic_settings(int depth) {
    PathTracerSettings pt;
    pt.max_depth = depth;
    pt.russian_roulette = false;
    pt.caustic_paths.enabled = true;
    return pt;
}

// A point light of intensity I at height 1 between a diffuse floor (albedo rho, y = 0) and
// a mirror ceiling (tint R, y = 2); the camera looks straight down at the floor. With two
// scattering events a floor point at distance r from the axis receives the light directly
// (cos / d^2 = 1 / (1 + r^2)^1.5) and through the mirror from the light's image at height
// 3 (R * 3 / (9 + r^2)^1.5), and sends rho / pi of it to the camera.
constexpr float kRho = 0.5f;
constexpr float kTint = 0.8f;
constexpr float kIntensity = 2.0f;

/// The floor's exact radiance where each camera ray meets it.
class MirroredPointLightFloor final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                               Sampler& /*sampler*/) const override {
        const float t = -ray.origin.y / ray.direction.y;
        const glm::vec3 p = ray.origin + t * ray.direction;
        const float r2 = p.x * p.x + p.z * p.z;
        const float direct = 1.0f / std::pow(1.0f + r2, 1.5f);
        const float mirrored = kTint * 3.0f / std::pow(9.0f + r2, 1.5f);
        return glm::vec3(kRho / kPi * kIntensity * (direct + mirrored));
    }
};

void build_mirror_room(Scene& scene) {
    add_quad(scene, {-20, 0, -20}, {40, 0, 0}, {0, 0, 40},
             scene.add_material(Material::diffuse(glm::vec3(kRho))));
    add_quad(scene, {-20, 2, -20}, {0, 0, 40}, {40, 0, 0},
             scene.add_material(Material::mirror(glm::vec3(kTint))));
    scene.add_point_light(PointLight{{0.0f, 1.0f, 0.0f}, glm::vec3(kIntensity)});
    scene.commit();
}

Camera looking_down(float near_clip = 0.0f) {
    CameraSettings cs;
    cs.near_clip = near_clip;
    cs.position = {0.0f, 1.5f, 0.0f};
    cs.look_at = {0.0f, 0.0f, 0.0f};
    cs.up = {0.0f, 0.0f, -1.0f};
    cs.vertical_fov_degrees = 60.0f;
    cs.width = cs.height = 16;
    cs.pixel_jitter = PixelJitter::Filter;  // a box over the pixel, as the splats' filter
    return Camera(cs);
}

TEST(CausticPaths, RenderAPointLightsImageInAMirrorInClosedForm) {
    Scene scene;
    build_mirror_room(scene);
    const Camera camera = looking_down();
    PathTracer split(caustic_settings(2));
    split.preprocess(scene);
    ASSERT_TRUE(split.splats());
    PathTracerSettings plain_settings = caustic_settings(2);
    plain_settings.caustic_paths.enabled = false;
    PathTracer plain(plain_settings);
    plain.preprocess(scene);
    const MirroredPointLightFloor exact;

    constexpr int kRenders = 16;
    constexpr int kSpp = 32;
    std::vector<std::vector<glm::dvec3>> with, without, expected;
    for (int k = 0; k < kRenders; ++k) {
        with.push_back(block_means(scene, camera, split, true, 10 + std::uint64_t(k), kSpp));
        without.push_back(block_means(scene, camera, plain, false, 40 + std::uint64_t(k), kSpp));
        expected.push_back(block_means(scene, camera, exact, false, 70 + std::uint64_t(k), kSpp));
    }
    expect_blocks_agree(with, expected, "caustic paths");
    // The test can fail: without the light paths the mirrored light is missing, by far
    // more than the tolerance.
    for (int blk = 0; blk < 16; ++blk) {
        const auto w = spread(without, blk, 0);
        const auto e = spread(expected, blk, 0);
        EXPECT_GT(e.mean - w.mean, 5.0 * std::sqrt(w.se2 + e.se2)) << "block " << blk;
    }
}

/// A diffuse floor under a mirror ceiling, lit by what add_light adds off to the side so
/// that the floor the camera sees is lit through the mirror alone: every path is caustic,
/// and the camera path hits the light in the mirror with full weight (a specular bounce)
/// -- which it must now leave to the light paths. Against brute force, which finds
/// nothing else here either.
template <class AddLight>
void expect_mirrored_light_matches_brute_force(AddLight add_light, std::uint64_t seed,
                                               const char* what, float near_clip = 0.0f) {
    Scene scene;
    add_quad(scene, {-20, 0, -20}, {40, 0, 0}, {0, 0, 40},
             scene.add_material(Material::diffuse(glm::vec3(kRho))));
    add_quad(scene, {-20, 2, -20}, {0, 0, 40}, {40, 0, 0},
             scene.add_material(Material::mirror(glm::vec3(kTint))));
    add_light(scene);
    scene.commit();
    const Camera camera = looking_down(near_clip);
    PathTracer split(caustic_settings(2));
    split.preprocess(scene);
    PathTracerSettings pt = caustic_settings(2);
    pt.caustic_paths.enabled = false;
    BruteForcePathTracer brute(pt);
    testing::expect_splatting_agrees(scene, camera, split, 64, brute, 512, seed, what);
}

TEST(CausticPaths, AgreeWithBruteForceUnderAQuadLightOnlyAMirrorSees) {
    // One-sided, facing the mirror.
    expect_mirrored_light_matches_brute_force(
        [](Scene& scene) {
            (void)scene.add_quad_light(QuadLight{
                {1.5f, 1.0f, -0.25f}, {0, 0, 0.5f}, {0.5f, 0, 0}, glm::vec3(4.0f), false});
        },
        900, "quad light seen through a mirror");
}

TEST(CausticPaths, AgreeWithBruteForceUnderASphereLightOnlyAMirrorSees) {
    // A sphere light (an emitter the camera path hits: Scene::light_of_hit) over a
    // diffuse shade that hides it from the floor in view, not from the mirror.
    expect_mirrored_light_matches_brute_force(
        [](Scene& scene) {
            (void)scene.add_sphere_light(
                SphereLight{Sphere{{1.9f, 1.3f, 0.0f}, 0.3f}, glm::vec3(4.0f)});
            add_quad(scene, {0.95f, 0.9f, -0.8f}, {1.65f, 0, 0}, {0, 0, 1.6f},
                     scene.add_material(Material::diffuse(glm::vec3(0.5f))));
        },
        1000, "sphere light seen through a mirror");
}

// A near clip plane (every glTF camera has one): camera rays pass a shade just under the
// camera that covers the whole view, and so must the light paths' joins to the lens
// (CameraWi::view_start), or every caustic is lost.
TEST(CausticPaths, AgreeWithBruteForceThroughANearClipPlane) {
    expect_mirrored_light_matches_brute_force(
        [](Scene& scene) {
            (void)scene.add_quad_light(QuadLight{
                {1.5f, 1.0f, -0.25f}, {0, 0, 0.5f}, {0.5f, 0, 0}, glm::vec3(4.0f), false});
            add_quad(scene, {-0.3f, 1.35f, -0.3f}, {0.6f, 0, 0}, {0, 0, 0.6f},
                     scene.add_material(Material::diffuse(glm::vec3(0.5f))));
        },
        1300, "near clip plane", 0.2f);
}

/// The split path tracer against `Reference` (brute force, which finds emitters only by
/// hitting them, or the plain MIS path tracer) at 16 times the samples, over independent
/// renders through a real camera, at max depth `depth`.
template <class Reference>
void expect_matches(const Scene& scene, int depth, int spp, std::uint64_t seed, const char* what) {
    const Camera camera(box_camera_settings(16));
    PathTracer split(caustic_settings(depth));
    split.preprocess(scene);
    PathTracerSettings pt = caustic_settings(depth);
    pt.caustic_paths.enabled = false;
    Reference reference(pt);
    reference.preprocess(scene);
    testing::expect_splatting_agrees(scene, camera, split, spp, reference, 16 * spp, seed, what);
}

TEST(CausticPaths, AgreeWithBruteForceUnderAQuadLightWithGlassAndMetal) {
    Scene scene;
    build_box(scene, false, true, true);
    expect_matches<BruteForcePathTracer>(scene, 3, 32, 500, "quad light, glass and metal");
}

// A light at infinity starts no light path: its caustics (the sky in the metal on the
// floor) stay with the camera path, and next-event estimation after a caster keeps it.
TEST(CausticPaths, AgreeWithBruteForceUnderASkyAndAPanel) {
    Scene scene;
    build_box_under_sky(scene);
    expect_matches<BruteForcePathTracer>(scene, 3, 32, 700, "sky and panel");
}

// The panel is a triangle-mesh light seen through the pane and in the metal (roughness
// 0.3, a caster); the caustics are the light paths', all other paths the camera path's.
// Against the plain path tracer (itself held to brute force by mis_test and bdpt_test):
// brute force's noise under the small panel would hide a missing caustic.
TEST(CausticPaths, AgreeWithThePlainPathTracerUnderATwoSidedPanelWithGlassAndMetal) {
    Scene scene;
    build_box(scene, true, true, true);
    expect_matches<PathTracer>(scene, 4, 64, 300, "panel, glass and metal");
}

// The report's kinds: a sphere light (an emitter the camera path can hit, light_of_hit)
// over a glass sphere and a mirror sphere, whose caustics land on the floor and walls.
TEST(CausticPaths, AgreeWithThePlainPathTracerUnderASphereLightWithGlassAndMirrorSpheres) {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.73f)));
    add_quad(scene, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, white);  // floor
    add_quad(scene, {-1, 0, -1}, {0, 2, 0}, {2, 0, 0}, white);  // back
    add_quad(scene, {-1, 2, -1}, {0, 0, 2}, {2, 0, 0}, white);  // ceiling
    (void)scene.add_sphere(Sphere{{-0.4f, 0.35f, 0.0f}, 0.35f},
                           scene.add_material(Material::dielectric(1.5f)));
    (void)scene.add_sphere(Sphere{{0.45f, 0.3f, -0.3f}, 0.3f},
                           scene.add_material(Material::mirror(glm::vec3(0.9f))));
    (void)scene.add_sphere_light(SphereLight{Sphere{{0.0f, 1.4f, 0.2f}, 0.1f}, glm::vec3(40.0f)});
    scene.commit();
    expect_matches<PathTracer>(scene, 4, 64, 1100, "sphere light, glass and mirror spheres");
}

TEST(CausticPaths, CastersAreSmoothMetalsAndGlassOnly) {
    EXPECT_TRUE(casts_caustics(Material::mirror(), 0.0f));
    EXPECT_TRUE(casts_caustics(Material::dielectric(1.5f), 0.0f));
    EXPECT_TRUE(casts_caustics(Material::conductor(Metal::Gold, 0.3f), 0.5f));
    EXPECT_FALSE(casts_caustics(Material::conductor(Metal::Gold, 0.6f), 0.5f));
    EXPECT_TRUE(casts_caustics(Material::rough_dielectric(1.5f, 0.5f), 0.5f));
    EXPECT_FALSE(casts_caustics(Material::rough_dielectric(1.5f, 0.51f), 0.5f));
    EXPECT_TRUE(casts_caustics(Material::metallic_roughness(glm::vec3(1.0f), 1.0f, 0.2f), 0.5f));
    EXPECT_TRUE(casts_caustics(
        Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.0f, 1.5f, 1.0f), 0.5f));
    // Any Lambert part, or a plastic's, is no caster.
    EXPECT_FALSE(casts_caustics(Material::metallic_roughness(glm::vec3(1.0f), 0.9f, 0.1f), 0.5f));
    EXPECT_FALSE(casts_caustics(Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.0f), 0.5f));
    EXPECT_FALSE(casts_caustics(Material::diffuse(glm::vec3(0.5f)), 1.0f));
    EXPECT_FALSE(casts_caustics(Material::emissive(glm::vec3(1.0f)), 1.0f));
}

TEST(CausticPaths, ChainOpensOnlyAfterASeenNonCaster) {
    using C = CausticChain;
    EXPECT_EQ(advance(C::Before, false), C::AtD);
    EXPECT_EQ(advance(C::Before, true), C::Broken);
    EXPECT_EQ(advance(C::AtD, true), C::Open);
    EXPECT_EQ(advance(C::AtD, false), C::Broken);
    EXPECT_EQ(advance(C::Open, true), C::Open);
    EXPECT_EQ(advance(C::Open, false), C::Broken);
    EXPECT_EQ(advance(C::Broken, true), C::Broken);
}

TEST(CausticPaths, RejectBadSettings) {
    for (const float r : {-0.1f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {
        PathTracerSettings pt;
        pt.caustic_paths.enabled = true;
        pt.caustic_paths.max_roughness = r;
        EXPECT_THROW(PathTracer{pt}, Error) << r;
    }
    PathTracerSettings pt;
    pt.caustic_paths.enabled = true;
    pt.guiding.enabled = true;
    EXPECT_THROW(PathTracer{pt}, Error);
}

// li() alone (no film to splat onto) renders every path, as without the setting: the same
// bits; and li_splatting falls back to it where light paths cannot reach the image (an
// orthographic camera, objects hidden from the camera).
TEST(CausticPaths, LiAloneAndFallbacksAreThePlainPathTracer) {
    Scene scene;
    build_box(scene, true, true, true);
    PathTracerSettings on = caustic_settings(4);
    on.russian_roulette = true;
    PathTracerSettings off = on;
    off.caustic_paths.enabled = false;
    PathTracer split(on);
    PathTracer plain(off);
    split.preprocess(scene);
    plain.preprocess(scene);
    CameraSettings ortho_settings = box_camera_settings(16);
    ortho_settings.projection = Projection::Orthographic;
    ortho_settings.pixel_jitter = PixelJitter::None;
    const Camera ortho(ortho_settings);
    Scene hiding;
    build_box(hiding, true, true, true);
    testing::add_hidden_sphere(hiding, Sphere{{0.0f, 1.0f, 1.5f}, 0.2f});
    SplatFilm film(16, 16, splat_filter_settings(ortho));
    const Camera persp(box_camera_settings(16));
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            for (int s = 0; s < 4; ++s) {
                const auto sampler = [&] {
                    return Sampler(SamplerKind::Independent, std::uint32_t(x), std::uint32_t(y),
                                   std::uint32_t(s), 9);
                };
                Sampler a = sampler();
                Sampler b = sampler();
                Sampler c = sampler();
                Sampler e = sampler();
                Sampler f = sampler();
                const Ray ray = persp.sample_ray(x, y, a).ray;
                (void)persp.sample_ray(x, y, b);
                (void)persp.sample_ray(x, y, c);
                const glm::vec3 ref = plain.li(scene, ray, a);
                EXPECT_EQ(split.li(scene, ray, b), ref) << x << "," << y;
                EXPECT_EQ(split.li_splatting(scene, ray, c, SplatTarget{&ortho, &film}), ref);
                (void)persp.sample_ray(x, y, e);
                (void)persp.sample_ray(x, y, f);
                EXPECT_EQ(split.li_splatting(hiding, ray, e, SplatTarget{&persp, &film}),
                          plain.li(hiding, ray, f));
            }
    const Image splats = film.resolve(4.0);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_EQ(splats.at(x, y), glm::vec3(0.0f));
}

TEST(CausticPaths, RenderIsIdenticalForAnyThreadCountAndTileSize) {
    PathTracer split(caustic_settings(4));
    testing::expect_box_render_identical_for_any_threads_and_tiles(split);
}

}  // namespace
}  // namespace librt
