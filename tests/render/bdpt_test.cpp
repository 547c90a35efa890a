// BidirectionalPathTracer against the brute-force path tracer (which only finds emitters
// by chance: the ground truth for area lights) and, for point lights, which brute force
// cannot find, against the MIS path tracer. Every comparison is of region means with
// tolerances of 5 standard errors from the samples' own variance; the light-tracing
// (t = 1) strategies are checked through a camera and a splat film, over independent
// renders.

#include "box_scene_test_util.h"
#include "film/camera_importance.h"
#include "integrator_test_util.h"

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/film/splat_film.h>
#include <librt/integrator/bdpt.h>
#include <librt/integrator/integrators.h>
#include <librt/light/point_light.h>
#include <librt/light/quad_light.h>
#include <librt/material/material.h>
#include <librt/render/renderer.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace librt {
namespace {

using testing::block_means;
using testing::box_camera;
using testing::box_camera_settings;
using testing::build_box;
using testing::build_box_under_sky;
using testing::expect_blocks_agree;
using testing::region;
using testing::render_stats;

/// Compares two renders block by block (4 x 4 blocks of 4 x 4 pixels) and over the image.
void expect_agree(const testing::StatImage& a, const testing::StatImage& b, const char* what) {
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx) {
            const auto ra = region(a, bx * 4, by * 4, bx * 4 + 4, by * 4 + 4);
            const auto rb = region(b, bx * 4, by * 4, bx * 4 + 4, by * 4 + 4);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(ra.mean[c], rb.mean[c], 5.0 * std::sqrt(ra.se2[c] + rb.se2[c]) + 1e-6)
                    << what << " block " << bx << "," << by << " channel " << c;
        }
    const auto ra = region(a, 0, 0, 16, 16);
    const auto rb = region(b, 0, 0, 16, 16);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(ra.mean[c], rb.mean[c], 5.0 * std::sqrt(ra.se2[c] + rb.se2[c]))
            << what << " image channel " << c;
}

/// Renders `scene` at max depth `depth` with the bidirectional tracer (128 spp; settings
/// `bd` with that depth) and with the reference integrator `Reference` (ref_spp; brute
/// force or the MIS path tracer), and expects them to agree (expect_agree).
template <class Reference>
void expect_matches(const Scene& scene, int depth, int ref_spp, std::uint64_t seed,
                    const char* what, BidirectionalSettings bd = {}) {
    PathTracerSettings pt;
    pt.max_depth = depth;
    pt.russian_roulette = false;
    bd.max_depth = depth;
    Reference reference(pt);
    BidirectionalPathTracer bdpt(bd);
    const auto ref = render_stats(scene, reference, box_camera(), ref_spp, seed);
    const auto img = render_stats(scene, bdpt, box_camera(), 128, seed + 1);
    expect_agree(img, ref, what);
}

TEST(Bidirectional, RejectsDepthOutOfRange) {
    EXPECT_THROW(BidirectionalPathTracer(BidirectionalSettings{-1}), Error);
    EXPECT_THROW(BidirectionalPathTracer(BidirectionalSettings{65}), Error);
}

TEST(Bidirectional, RejectsALightPathFractionOutsideZeroToOneAndANegativeRouletteDepth) {
    for (const float f : {0.0f, -0.5f, 1.5f, std::nanf("")}) {
        BidirectionalSettings bd;
        bd.light_path_fraction = f;
        EXPECT_THROW(BidirectionalPathTracer{bd}, Error) << f;
    }
    BidirectionalSettings bd;
    bd.russian_roulette_depth = -1;
    EXPECT_THROW(BidirectionalPathTracer{bd}, Error);
    bd.russian_roulette_depth = 0;
    bd.light_path_fraction = 0.01f;
    EXPECT_NO_THROW(BidirectionalPathTracer{bd});
}

TEST(Bidirectional, AgreesWithBruteForceUnderAQuadLight) {
    Scene scene;
    build_box(scene, false, false, false);
    expect_matches<BruteForcePathTracer>(scene, 3, 1024, 1, "quad light");
}

TEST(Bidirectional, AgreesWithBruteForceUnderATwoSidedPanelWithGlassAndMetal) {
    Scene scene;
    build_box(scene, true, true, true);
    expect_matches<BruteForcePathTracer>(scene, 4, 2048, 3, "panel");
}

// A light subpath in a quarter of the samples, and roulette from the first bounce on: the
// light-subpath strategies' contributions are divided by the fraction and every weight
// counts the samples each strategy gets (a wrong count breaks the partition of unity and
// shows as a bias); roulette leaves the weights alone and the mean unchanged.
TEST(Bidirectional, AgreesWithBruteForceWithAQuarterOfTheLightPathsAndRoulette) {
    Scene scene;
    build_box(scene, true, true, true);
    BidirectionalSettings bd;
    bd.light_path_fraction = 0.25f;
    bd.russian_roulette_depth = 1;
    expect_matches<BruteForcePathTracer>(scene, 4, 2048, 13, "a quarter of the light paths", bd);
}

TEST(Bidirectional, AgreesWithBruteForceWithoutRoulette) {
    Scene scene;
    build_box(scene, true, true, true);
    BidirectionalSettings bd;
    bd.russian_roulette = false;
    expect_matches<BruteForcePathTracer>(scene, 4, 2048, 17, "no roulette", bd);
}

// A light at infinity starts no light subpath; when the light sampler picks it for the
// light subpath, next-event estimation must still run (it draws its own light), and the
// panel's paths keep their bidirectional weights. The box is open toward the camera, so
// the sky lights it too.
TEST(Bidirectional, AgreesWithBruteForceUnderASkyAndAPanel) {
    Scene scene;
    build_box_under_sky(scene);
    expect_matches<BruteForcePathTracer>(scene, 3, 1024, 7, "sky and panel");
}

TEST(Bidirectional, AgreesWithThePathTracerUnderAPointLight) {
    Scene scene;
    build_box(scene, false, true, true);
    (void)scene.add_point_light(PointLight::from_power({0.3f, 1.5f, 0.0f}, glm::vec3(20.0f)));
    scene.commit();
    expect_matches<PathTracer>(scene, 3, 512, 5, "point light");
}

/// The bidirectional tracer (max depth 3) through `camera` and a splat film against the
/// brute-force tracer through the same camera, over 8 independent renders.
void expect_splatting_matches_brute_force(const Scene& scene, const Camera& camera,
                                          std::uint64_t seed, const char* what,
                                          BidirectionalSettings bd = {}) {
    bd.max_depth = 3;
    BidirectionalPathTracer bdpt(bd);
    bdpt.preprocess(scene);
    PathTracerSettings pt;
    pt.max_depth = 3;
    pt.russian_roulette = false;
    BruteForcePathTracer brute(pt);
    ASSERT_TRUE(bdpt.splats());
    testing::expect_splatting_agrees(scene, camera, bdpt, 16, brute, 256, seed, what);
}

// The t = 1 strategies through a real camera and a splat film: per render, each pixel's
// mean plus the resolved splats; over K independent renders (seeds), block means agree
// with the brute-force tracer's through the same camera.
TEST(Bidirectional, LightTracingStrategiesAgreeThroughASplatFilm) {
    Scene scene;
    build_box(scene, true, true, false);
    expect_splatting_matches_brute_force(scene, Camera(box_camera_settings(16)), 100,
                                         "light tracing");
}

// The t = 1 strategies in a third of the samples: their splats are divided by the
// fraction, as the other light-subpath strategies' contributions are.
TEST(Bidirectional, LightTracingAgreesThroughASplatFilmWithAThirdOfTheLightPaths) {
    Scene scene;
    build_box(scene, true, true, false);
    BidirectionalSettings bd;
    bd.light_path_fraction = 1.0f / 3.0f;
    bd.russian_roulette_depth = 1;
    expect_splatting_matches_brute_force(scene, Camera(box_camera_settings(16)), 700,
                                         "a third of the light paths", bd);
}

// A mirror on the floor under a light that faces down: the ceiling is lit mostly by light
// the mirror sends up, which only the camera's BSDF rays (s = 0) and light subpaths joined
// to the lens (t = 1) find, and the weights give t = 1 nearly all of it. In a quarter of
// the samples those splats must count four times: left undivided the ceiling reads about
// a quarter of its light, far outside the tolerance.
TEST(Bidirectional, LightTracingOfAMirrorCausticAgreesWithAQuarterOfTheLightPaths) {
    Scene scene;
    build_box(scene, false, false, false);
    testing::add_quad(scene, {-0.4f, 0.001f, -0.4f}, {0.8f, 0, 0}, {0, 0, 0.8f},
                      scene.add_material(Material::mirror()));
    scene.commit();
    BidirectionalSettings bd;
    bd.light_path_fraction = 0.25f;
    bd.russian_roulette_depth = 1;
    expect_splatting_matches_brute_force(scene, Camera(box_camera_settings(16)), 900,
                                         "mirror caustic, a quarter of the light paths", bd);
}

// Camera rays pass what a light path's join to the lens would otherwise stop at: the space
// before a near clip plane (here a wall just in front of the camera), which the join leaves
// out (CameraWi::view_start), and objects hidden from the camera, for which the t = 1
// strategies are left out. Either way the image still matches brute force.
TEST(Bidirectional, AgreesWithBruteForceThroughANearClipPlane) {
    Scene scene;
    build_box(scene, false, false, true);
    testing::add_quad(scene, {-3.0f, -2.0f, 3.0f}, {6.0f, 0, 0}, {0, 6.0f, 0},
                      scene.add_material(Material::diffuse(glm::vec3(0.5f))));
    scene.commit();
    CameraSettings cs = box_camera_settings(16);
    cs.near_clip = 0.6f;
    expect_splatting_matches_brute_force(scene, Camera(cs), 300, "near clip plane");
}

TEST(Bidirectional, AgreesWithBruteForceThroughAnObjectHiddenFromTheCamera) {
    Scene scene;
    build_box(scene, false, false, true);
    testing::add_hidden_sphere(scene, Sphere{{0.0f, 1.0f, 2.0f}, 0.5f});
    expect_splatting_matches_brute_force(scene, Camera(box_camera_settings(16)), 500,
                                         "hidden object");
}

}  // namespace
}  // namespace librt

namespace librt {
namespace {

// Through render(): the splats of the t = 1 strategies land in pixels other threads
// render, and the image is still the same bits for any thread count and tile size.
TEST(Bidirectional, RenderIsIdenticalForAnyThreadCountAndTileSize) {
    BidirectionalSettings bd;
    bd.max_depth = 4;
    BidirectionalPathTracer bdpt(bd);
    testing::expect_box_render_identical_for_any_threads_and_tiles(bdpt);
}

}  // namespace
}  // namespace librt
