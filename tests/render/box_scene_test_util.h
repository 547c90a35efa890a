#pragma once

// The small open box the bidirectional and caustic-path tests render (a two-sided panel or
// a quad light, a glass pane, a glossy metal), and the check of splatting integrators over
// K independent renders through a real camera: per render each 4 x 4 block's mean of the
// pixels plus the resolved splats, compared with 5 standard errors of the renders' spread.

#include "film/camera_importance.h"
#include "integrator_test_util.h"

#include <librt/film/camera.h>
#include <librt/film/splat_film.h>
#include <librt/integrator/integrator.h>
#include <librt/light/environment_light.h>
#include <librt/light/quad_light.h>
#include <librt/material/material.h>
#include <librt/render/renderer.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace librt::testing {

inline void add_quad(Scene& scene, glm::vec3 corner, glm::vec3 e0, glm::vec3 e1,
                     std::uint32_t material) {
    TriangleMesh m;
    m.positions = {corner, corner + e0, corner + e0 + e1, corner + e1};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(m, material);
}

/// A 2 x 2 x 2 box open toward the camera (+z): white floor and ceiling, red and green
/// walls, a white back wall. `panel`: a two-sided emissive triangle panel 1 cm under the
/// ceiling (the case bidirectional paths are for); else a one-sided quad light.
/// `glass_pane`: a thin smooth pane standing on the floor; `glossy`: a gold-like metal
/// slab of roughness 0.3 leaning on the back wall.
inline void build_box(Scene& scene, bool panel, bool glass_pane, bool glossy) {
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.73f)));
    const auto red = scene.add_material(Material::diffuse({0.65f, 0.05f, 0.05f}));
    const auto green = scene.add_material(Material::diffuse({0.12f, 0.45f, 0.15f}));
    add_quad(scene, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, white);  // floor
    add_quad(scene, {-1, 2, -1}, {0, 0, 2}, {2, 0, 0}, white);  // ceiling
    add_quad(scene, {-1, 0, -1}, {0, 2, 0}, {2, 0, 0}, white);  // back
    add_quad(scene, {-1, 0, -1}, {0, 0, 2}, {0, 2, 0}, red);    // left
    add_quad(scene, {1, 0, -1}, {0, 2, 0}, {0, 0, 2}, green);   // right
    if (panel) {
        Material light = Material::metallic_roughness(glm::vec3(0.0f), 0.0f, 1.0f);
        light.emission = glm::vec3(12.0f, 10.0f, 8.0f);
        add_quad(scene, {-0.25f, 1.99f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f},
                 scene.add_material(light));
    } else {
        (void)scene.add_quad_light(QuadLight{
            {-0.25f, 1.99f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, glm::vec3(10.0f), false});
    }
    if (glass_pane) {
        // A thin smooth pane standing on the floor (a Null lobe) and a block behind it.
        add_quad(scene, {-0.6f, 0.0f, 0.2f}, {0.8f, 0, 0}, {0, 0.8f, 0},
                 scene.add_material(
                     Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.0f, 1.5f, 1.0f)));
    }
    if (glossy) {
        add_quad(scene, {0.1f, 0.0f, -0.6f}, {0.6f, 0.6f, 0}, {0, 0, 0.6f},
                 scene.add_material(Material::metallic_roughness({1.0f, 0.8f, 0.4f}, 1.0f, 0.3f)));
    }
    scene.commit();
}

/// build_box with the two-sided panel and the glossy metal, under a constant sky too (the
/// box is open toward the camera, so the sky lights it): a light at infinity, which starts
/// no light path, beside one that does.
inline void build_box_under_sky(Scene& scene) {
    build_box(scene, true, false, true);
    (void)scene.add_environment_light(EnvironmentLight::constant({0.6f, 0.7f, 0.9f}));
    scene.commit();
}

/// A grey diffuse sphere hidden from the camera (camera rays pass it; it still shadows and
/// reflects for every other ray), then commit().
inline void add_hidden_sphere(Scene& scene, const Sphere& sphere) {
    scene.set_camera_visible(
        scene.add_sphere(sphere, scene.add_material(Material::diffuse(glm::vec3(0.5f)))), false);
    scene.commit();
}

/// The box seen from the open side, through pixel centres (render_stats' camera).
inline Pinhole box_camera() {
    Pinhole cam;
    cam.eye = {0.0f, 1.0f, 3.4f};
    cam.fov_degrees = 40.0f;
    cam.width = cam.height = 16;
    return cam;
}

/// box_camera() as a librt Camera of size x size pixels, with the report's Gaussian jitter.
inline CameraSettings box_camera_settings(int size) {
    CameraSettings cs;
    cs.position = {0.0f, 1.0f, 3.4f};
    cs.look_at = {0.0f, 1.0f, 0.0f};
    cs.vertical_fov_degrees = 40.0f;
    cs.width = cs.height = size;
    cs.pixel_jitter = PixelJitter::Gaussian;
    return cs;
}

/// Block means ([block][channel], 4 x 4 blocks of 4 x 4 pixels) of one render of a 16 x 16
/// camera at spp samples per pixel: each pixel's mean of li (li_splatting onto a SplatFilm
/// when `splat`) plus, when `splat`, the film's resolved splats.
inline std::vector<glm::dvec3> block_means(const Scene& scene, const Camera& camera,
                                           const Integrator& integrator, bool splat,
                                           std::uint64_t seed, int spp) {
    SplatFilm film(16, 16, splat_filter_settings(camera));
    std::vector<glm::dvec3> sum(256, glm::dvec3(0.0));
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            for (int s = 0; s < spp; ++s) {
                Sampler sampler(SamplerKind::Independent, std::uint32_t(x), std::uint32_t(y),
                                std::uint32_t(s), seed);
                const CameraRay r = camera.sample_ray(x, y, sampler);
                const glm::vec3 l = splat ? integrator.li_splatting(scene, r.ray, sampler,
                                                                    SplatTarget{&camera, &film})
                                          : integrator.li(scene, r.ray, sampler);
                sum[std::size_t(y * 16 + x)] += glm::dvec3(l) / double(spp);
            }
    if (splat) {
        const Image splats = film.resolve(double(spp));
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                sum[std::size_t(y * 16 + x)] += glm::dvec3(splats.at(x, y));
    }
    std::vector<glm::dvec3> blocks(16, glm::dvec3(0.0));
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            blocks[std::size_t((y / 4) * 4 + x / 4)] += sum[std::size_t(y * 16 + x)] / 16.0;
    return blocks;
}

/// Mean and squared standard error of one block's channel over independent renders.
struct RenderSpread {
    double mean = 0.0;
    double se2 = 0.0;
};

inline RenderSpread spread(const std::vector<std::vector<glm::dvec3>>& renders, int block,
                           int channel) {
    const auto k = double(renders.size());
    RenderSpread r;
    for (const auto& b : renders) r.mean += b[std::size_t(block)][channel] / k;
    double var = 0.0;
    for (const auto& b : renders)
        var += std::pow(b[std::size_t(block)][channel] - r.mean, 2) / (k - 1.0);
    r.se2 = var / k;
    return r;
}

/// Every block's channel of the renders `a` agrees with `b`'s within 5 standard errors.
inline void expect_blocks_agree(const std::vector<std::vector<glm::dvec3>>& a,
                                const std::vector<std::vector<glm::dvec3>>& b, const char* what) {
    for (int blk = 0; blk < 16; ++blk)
        for (int c = 0; c < 3; ++c) {
            const RenderSpread sa = spread(a, blk, c);
            const RenderSpread sb = spread(b, blk, c);
            EXPECT_NEAR(sa.mean, sb.mean, 5.0 * std::sqrt(sa.se2 + sb.se2) + 1e-6)
                << what << " block " << blk << " channel " << c;
        }
}

/// `integrator` (li_splatting onto a splat film, spp samples per pixel) against `reference`
/// (li alone, reference_spp) through the same camera: expect_blocks_agree over `renders`
/// independent renders, seeds from `seed` and from seed + 100.
inline void expect_splatting_agrees(const Scene& scene, const Camera& camera,
                                    const Integrator& integrator, int spp,
                                    const Integrator& reference, int reference_spp,
                                    std::uint64_t seed, const char* what, int renders = 8) {
    std::vector<std::vector<glm::dvec3>> a, b;
    for (int k = 0; k < renders; ++k) {
        a.push_back(block_means(scene, camera, integrator, true, seed + std::uint64_t(k), spp));
        b.push_back(block_means(scene, camera, reference, false, seed + 100 + std::uint64_t(k),
                                reference_spp));
    }
    expect_blocks_agree(a, b, what);
}

/// Renders the box (panel, glass pane and glossy metal) through render() with one thread
/// and 16-pixel tiles, then two threads and 5-pixel tiles: a splatting integrator's splats
/// land in pixels other threads render, and the image must still be the same bits (and
/// not black).
inline void expect_box_render_identical_for_any_threads_and_tiles(Integrator& integrator) {
    Scene scene;
    build_box(scene, true, true, true);
    const Camera camera(box_camera_settings(24));
    RenderSettings rs;
    rs.samples_per_pixel = 4;
    rs.threads = 1;
    rs.tile_size = 16;
    const Image one = render(scene, camera, integrator, rs);
    rs.threads = 2;
    rs.tile_size = 5;
    const Image two = render(scene, camera, integrator, rs);
    ASSERT_EQ(one.width, two.width);
    ASSERT_EQ(one.height, two.height);
    double sum = 0.0;
    for (int y = 0; y < one.height; ++y)
        for (int x = 0; x < one.width; ++x) {
            ASSERT_EQ(one.at(x, y), two.at(x, y)) << x << "," << y;
            sum += double(one.at(x, y).x);
        }
    EXPECT_GT(sum, 0.0);
}

}  // namespace librt::testing
