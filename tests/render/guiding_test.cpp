// Path guiding (PathTracerSettings::guiding): the directional quadtree is a density that
// its sampler follows (chi-square) and that integrates to 1 over the sphere; a guided
// render of a room lit only through a gap agrees with the unguided one within standard
// errors derived from the sample variance (whole image and 4 x 4 blocks); a guided render
// is bit-identical across runs, thread counts and tile sizes; guiding off changes nothing.

#include "integrator/guiding/quad_tree.h"
#include "integrator/guiding/sd_tree.h"
#include "integrator_test_util.h"
#include "sampling/chi_square.h"
#include "sampling/sanitizer_scale.h"

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/geometry/mesh.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/warp.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace librt {
namespace {

using guiding::QuadTree;
using testing::Pinhole;
using testing::region;
using testing::RegionEstimate;
using testing::StatImage;

/// A direction peaked around `axis` (a cosine power lobe drawn from u) plus, with
/// probability 0.3, a uniform one: a distribution with structure at many scales.
glm::vec3 peaked_direction(Pcg32& rng, const glm::vec3& axis) {
    const float choice = rng.next_float();
    const glm::vec2 u{rng.next_float(), rng.next_float()};
    if (choice < 0.3f) return sample_uniform_sphere(u);
    // cos theta = u^(1/(n+1)), n = 200: a narrow lobe.
    const float cos_t = std::pow(u.x, 1.0f / 201.0f);
    const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
    const float phi = 2.0f * kPi * u.y;
    return Frame::from_normal(axis).to_world({sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t});
}

/// A quadtree trained like the SD-tree's: counts of peaked directions per cell, refined
/// by flux, four times.
QuadTree trained_quadtree() {
    Pcg32 rng(7, 11);
    const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    QuadTree tree;
    for (int round = 0; round < 4; ++round) {
        std::vector<double> flux(tree.slot_count(), 0.0);
        for (int i = 0; i < 20000; ++i)
            flux[tree.leaf_slot(guiding::direction_to_square(peaked_direction(rng, axis)))] += 1.0;
        tree.set_leaf_flux(flux);
        if (round < 3) tree = tree.refined(0.01f, 12, 1u << 16u);
    }
    return tree;
}

TEST(GuidingQuadTree, CylindricalMapRoundTrips) {
    Pcg32 rng(3, 5);
    for (int i = 0; i < 10000; ++i) {
        const glm::vec3 d = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        const glm::vec3 back = guiding::square_to_direction(guiding::direction_to_square(d));
        EXPECT_NEAR(glm::length(back - d), 0.0f, 1e-5f) << i;
    }
}

// The node cap bounds memory whatever the threshold: a threshold far below one sample's
// flux would split every cell down to max_depth, 4^12 cells, without it.
TEST(GuidingQuadTree, RefinementStopsAtTheNodeCap) {
    const QuadTree tree = trained_quadtree();
    const QuadTree capped = tree.refined(1e-9f, 12, 500);
    EXPECT_LE(capped.nodes().size(), 500u);
    EXPECT_GE(capped.nodes().size(), 400u);
    EXPECT_EQ(capped.total(), 0.0f);
}

TEST(GuidingQuadTree, RefinementFollowsTheFlux) {
    const QuadTree tree = trained_quadtree();
    // The lobe holds most of the flux, so its cells are split deep; the uniform rest is
    // spread thin and stays coarse.
    EXPECT_GE(tree.depth(), 5);
    EXPECT_LE(tree.depth(), 12);
    EXPECT_GT(tree.nodes().size(), 20u);
    EXPECT_GT(tree.total(), 0.0f);
}

// The density integrates to 1: exactly over the square (a grid of the deepest cells'
// size, whose midpoints each lie in one cell) and, on the sphere, by a uniform Monte
// Carlo estimate of the integral of pdf(d) within 5 standard errors.
TEST(GuidingQuadTree, PdfIntegratesToOne) {
    const QuadTree tree = trained_quadtree();
    const int n = 1 << 11;  // finer than depth 11's cells (depth <= 12 checked above: 2^-11)
    ASSERT_LE(tree.depth(), 11);
    double sum = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            sum += tree.pdf_square({(float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)});
    EXPECT_NEAR(sum / (double(n) * double(n)), 1.0, 1e-4);

    Pcg32 rng(19, 23);
    const int m = 400000;
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < m; ++i) {
        const glm::vec3 d = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        const double v = double(tree.pdf(d)) / double(uniform_sphere_pdf());
        s += v;
        s2 += v * v;
    }
    const double mean = s / m, se = std::sqrt((s2 / m - mean * mean) / m);
    EXPECT_NEAR(mean, 1.0, 5.0 * se) << "se " << se;
}

// sample() follows pdf(): 64 x 64 cells of the square; each cell's expected count is the
// integral of pdf_square over it, exact from the midpoints of a 2^11 grid (cells of the
// tree are coarser), against 10^6 samples (a tenth under a sanitizer). Pearson's
// chi-square, p >= 0.001.
TEST(GuidingQuadTree, SampleMatchesPdfChiSquare) {
    const QuadTree tree = trained_quadtree();
    const int cells = 64, fine = 1 << 11, per = fine / cells;
    std::vector<double> expected(std::size_t(cells * cells), 0.0);
    const double samples = librt::testing::scaled_samples(1'000'000);
    for (int y = 0; y < fine; ++y)
        for (int x = 0; x < fine; ++x) {
            const float p =
                tree.pdf_square({(float(x) + 0.5f) / float(fine), (float(y) + 0.5f) / float(fine)});
            expected[std::size_t((y / per) * cells + x / per)] +=
                double(p) * samples / (double(fine) * double(fine));
        }
    std::vector<double> observed(expected.size(), 0.0);
    Pcg32 rng(41, 43);
    for (int i = 0; i < int(samples); ++i) {
        const glm::vec2 p = tree.sample_square({rng.next_float(), rng.next_float()});
        ASSERT_TRUE(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f) << p.x << " " << p.y;
        observed[std::size_t(int(p.y * cells) * cells + int(p.x * cells))] += 1.0;
    }
    const testing::ChiSquareResult r = testing::chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.summary();
    EXPECT_GE(r.p_value, 1e-3) << r.summary();
    // And the sphere's density is the square's over 4 pi at the sampled directions.
    for (int i = 0; i < 1000; ++i) {
        const glm::vec2 u{rng.next_float(), rng.next_float()};
        const glm::vec3 d = tree.sample(u);
        EXPECT_NEAR(tree.pdf(d) * 4.0f * kPi, tree.pdf_square(guiding::direction_to_square(d)),
                    1e-4f * tree.pdf_square(guiding::direction_to_square(d)));
    }
}

TEST(GuidingSettingsCheck, BadValuesNameTheParameter) {
    const auto refused = [](auto change, const char* name) {
        PathTracerSettings s;
        change(s.guiding);
        try {
            PathTracer p(s);
            ADD_FAILURE() << name << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    };
    refused([](GuidingSettings& g) { g.training_passes = 0; }, "guiding.training_passes");
    refused([](GuidingSettings& g) { g.bsdf_fraction = 0.0f; }, "guiding.bsdf_fraction");
    refused([](GuidingSettings& g) { g.bsdf_fraction = NAN; }, "guiding.bsdf_fraction");
    refused([](GuidingSettings& g) { g.flux_threshold = 1.0f; }, "guiding.flux_threshold");
    refused([](GuidingSettings& g) { g.spatial_threshold = 0; }, "guiding.spatial_threshold");
    refused([](GuidingSettings& g) { g.max_quadtree_depth = 21; }, "guiding.max_quadtree_depth");
}

/// A closed room (the report's walls) whose only light hangs in an open-topped white box
/// below the ceiling: light reaches the room through the gap, by the ceiling. Next-event
/// estimation from the room finds the light occluded almost everywhere, and cosine
/// sampling rarely finds the bright patch of ceiling: the case guiding is for.
void build_lamp_room(Scene& scene) {
    auto diffuse = [&](glm::vec3 a) { return scene.add_material(Material::diffuse(a)); };
    scene.add_sphere({{0, -1000, 0}, 990}, diffuse({0.8f, 0.8f, 0.8f}));
    scene.add_sphere({{0, 0, -1050}, 940}, diffuse({0.7f, 0.7f, 0.9f}));
    scene.add_sphere({{0, 0, 1000}, 940}, diffuse({0.8f, 0.8f, 0.6f}));
    scene.add_sphere({{1000, 0, 0}, 940}, diffuse({0.8f, 0.2f, 0.2f}));
    scene.add_sphere({{-1000, 0, 0}, 940}, diffuse({0.2f, 0.8f, 0.2f}));
    scene.add_sphere({{0, 1000, 0}, 940}, diffuse({0.9f, 0.9f, 0.9f}));
    scene.add_sphere({{-15, -2, -20}, 8}, diffuse({0.9f, 0.9f, 0.9f}));
    // The lamp box: x, z in [-6, 6], y in [36, 50]; its lid has a 10 x 10 hole, so the lamp
    // throws a small bright patch on the ceiling, and that patch lights the room.
    TriangleMesh box;
    const float x0 = -6, x1 = 6, y0 = 36, y1 = 50, z0 = -36, z1 = -24, zc = -30;
    const float h = 5.0f;
    box.positions = {{x0, y0, z0},
                     {x1, y0, z0},
                     {x1, y0, z1},
                     {x0, y0, z1},
                     {x0, y1, z0},
                     {x1, y1, z0},
                     {x1, y1, z1},
                     {x0, y1, z1},
                     // the hole's corners in the lid
                     {-h, y1, zc - h},
                     {h, y1, zc - h},
                     {h, y1, zc + h},
                     {-h, y1, zc + h}};
    box.triangles = {{0, 1, 2},  {0, 2, 3},    // bottom
                     {0, 1, 5},  {0, 5, 4},    // z0 side
                     {3, 2, 6},  {3, 6, 7},    // z1 side
                     {0, 3, 7},  {0, 7, 4},    // x0 side
                     {1, 2, 6},  {1, 6, 5},    // x1 side
                     {4, 5, 9},  {4, 9, 8},    // lid around the hole: z0 strip
                     {5, 6, 10}, {5, 10, 9},   // x1 strip
                     {6, 7, 11}, {6, 11, 10},  // z1 strip
                     {7, 4, 8},  {7, 8, 11}};  // x0 strip
    scene.add_mesh(std::move(box), diffuse({0.8f, 0.8f, 0.8f}));
    scene.add_sphere_light({{{0, 42, -30}, 2.5f}, glm::vec3(400.0f)});
    scene.commit();
}

CameraSettings lamp_room_camera(int size) {
    CameraSettings c;  // the report's: at (0, 0, 55) looking down -z, 60 degrees
    c.width = c.height = size;
    return c;
}

PathTracerSettings guided_settings() {
    PathTracerSettings s{5, false};
    s.guiding.enabled = true;
    s.guiding.training_passes = 5;
    // Small images record few vertices: a smaller c than the paper's lets the spatial
    // tree split at all (the paper's 12000 is for megapixel images).
    s.guiding.spatial_threshold = 300;
    return s;
}

/// Per-pixel statistics of spp pixel-centre samples after the integrator's training
/// passes (train() on the same view).
StatImage trained_stats(const Scene& scene, PathTracer& integrator, int size, int spp,
                        std::uint64_t seed) {
    integrator.preprocess(scene);
    RenderSettings rs;
    rs.threads = 2;
    rs.seed = seed;
    // Trained on a larger view than the test image: more vertices, a deeper tree.
    const int train_size = 3 * size;
    const RenderStats training = train(scene, Camera(lamp_room_camera(train_size)), integrator, rs);
    EXPECT_EQ(training.training_passes, integrator.settings().guiding.enabled
                                            ? integrator.settings().guiding.training_passes
                                            : 0);
    Pinhole cam = testing::room_camera(size);
    StatImage img{size, size, std::vector<testing::PixelStats>(std::size_t(size * size))};
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const Ray ray = cam.ray(x, y);
            for (int s = 0; s < spp; ++s) {
                Sampler sampler(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s), seed);
                img.pixels[std::size_t(y * size + x)].add(integrator.li(scene, ray, sampler));
            }
        }
    return img;
}

// |a - b| <= k * sqrt(se_a^2 + se_b^2) per channel.
void expect_same(const RegionEstimate& a, const RegionEstimate& b, double k,
                 const std::string& where) {
    for (int c = 0; c < 3; ++c) {
        const double tol = k * std::sqrt(a.se2[c] + b.se2[c]);
        EXPECT_LE(std::fabs(a.mean[c] - b.mean[c]), tol)
            << where << " channel " << c << ": " << a.mean[c] << " vs " << b.mean[c] << " (se "
            << std::sqrt(a.se2[c]) << ", " << std::sqrt(b.se2[c]) << ")";
    }
}

// Unbiased: guided and unguided estimate the same image. Independent seeds; 5 standard
// errors over the whole image and each of 4 x 4 blocks (17 comparisons x 3 channels: a
// false alarm about once in 10^4 runs at normal errors).
TEST(Guiding, GuidedRenderAgreesWithUnguidedOnALampRoom) {
    Scene scene;
    build_lamp_room(scene);
    const int size = 16, spp = 256;
    PathTracer guided(guided_settings());
    PathTracer plain(PathTracerSettings{5, false});
    const StatImage a = trained_stats(scene, guided, size, spp, 101);
    const StatImage b = trained_stats(scene, plain, size, spp, 202);
    EXPECT_GT(guided.guiding_leaf_count(), 1u) << "the spatial tree never split";
    EXPECT_EQ(guided.nonfinite_count() + plain.nonfinite_count(), 0u);
    expect_same(region(a, 0, 0, size, size), region(b, 0, 0, size, size), 5.0, "whole image");
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx) {
            const int x0 = bx * size / 4, y0 = by * size / 4;
            const int x1 = (bx + 1) * size / 4, y1 = (by + 1) * size / 4;
            expect_same(region(a, x0, y0, x1, y1), region(b, x0, y0, x1, y1), 5.0,
                        "block " + std::to_string(bx) + "," + std::to_string(by));
        }
    // Power: the whole image's difference is resolved to 10% of its value.
    const RegionEstimate wa = region(a, 0, 0, size, size), wb = region(b, 0, 0, size, size);
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::sqrt(wa.se2[c] + wb.se2[c]), 0.1 * wb.mean[c]);
}

// The same on the report's room with a visible sphere light, mirror and glass (mis_test's
// soft-shadow room): light samples there carry most of the image, so the light strategy's
// MIS weight must use the guided mixture's density, or the weights no longer sum to one.
TEST(Guiding, GuidedRenderAgreesWithUnguidedOnTheReportRoom) {
    Scene scene;
    testing::add_room(scene);
    scene.add_sphere_light({{{-10, 20, 40}, 10}, glm::vec3(50.0f)});
    scene.commit();
    const int size = 16, spp = 256;
    PathTracer guided(guided_settings());
    PathTracer plain(PathTracerSettings{5, false});
    const StatImage a = trained_stats(scene, guided, size, spp, 303);
    const StatImage b = trained_stats(scene, plain, size, spp, 404);
    EXPECT_GT(guided.guiding_leaf_count(), 1u) << "the spatial tree never split";
    expect_same(region(a, 0, 0, size, size), region(b, 0, 0, size, size), 5.0, "whole image");
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx) {
            const int x0 = bx * size / 4, y0 = by * size / 4;
            const int x1 = (bx + 1) * size / 4, y1 = (by + 1) * size / 4;
            expect_same(region(a, x0, y0, x1, y1), region(b, x0, y0, x1, y1), 5.0,
                        "block " + std::to_string(bx) + "," + std::to_string(by));
        }
    const RegionEstimate wa = region(a, 0, 0, size, size), wb = region(b, 0, 0, size, size);
    // Power: the whole image's difference is resolved to 2.5% of its value.
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::sqrt(wa.se2[c] + wb.se2[c]), 0.025 * wb.mean[c]);
}

Image guided_render(const Scene& scene, int threads, int tile, SamplerKind kind) {
    PathTracer integrator(guided_settings());
    RenderSettings rs;
    rs.samples_per_pixel = 8;
    rs.threads = threads;
    rs.tile_size = tile;
    rs.sampler = kind;
    rs.seed = 5;
    CameraSettings c = lamp_room_camera(24);
    c.pixel_jitter = PixelJitter::Gaussian;
    RenderStats stats;
    Image image = render(scene, Camera(c), integrator, rs, &stats);
    EXPECT_EQ(stats.training_passes, 5);
    EXPECT_GT(integrator.guiding_leaf_count(), 1u);
    return image;
}

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// Records are fixed-point integers added atomically, so what is learned does not depend
// on which thread recorded what, or in what order: bit-identical for any thread count and
// tile size, with either sampler.
TEST(Guiding, BitIdenticalAcrossRunsThreadsAndTiles) {
    Scene scene;
    build_lamp_room(scene);
    for (const SamplerKind kind : {SamplerKind::Independent, SamplerKind::Sobol}) {
        const Image one = guided_render(scene, 1, 16, kind);
        EXPECT_TRUE(same_bits(one, guided_render(scene, 1, 16, kind))) << "run to run";
        EXPECT_TRUE(same_bits(one, guided_render(scene, 2, 16, kind))) << "1 vs 2 threads";
        EXPECT_TRUE(same_bits(one, guided_render(scene, 2, 5, kind))) << "tile 16 vs 5";
    }
}

// render_progressive trains the same guide as render() (training depends only on the seed),
// so its film in passes of 3 samples equals the one-shot render bit for bit, and a film
// continued by a second call (which trains again, identically) does too.
TEST(Guiding, ProgressiveEqualsOneShot) {
    Scene scene;
    build_lamp_room(scene);
    CameraSettings c = lamp_room_camera(20);
    c.pixel_jitter = PixelJitter::Gaussian;
    const Camera camera(c);
    PathTracer one_shot(guided_settings());
    RenderSettings rs;
    rs.samples_per_pixel = 8;
    rs.seed = 9;
    rs.adaptive.enabled = false;  // kept training passes: an image of equal counts (and resumable)
    const Image image = render(scene, camera, one_shot, rs);
    PathTracer progressive(guided_settings());
    ProgressiveSettings ps;
    ps.render = rs;
    ps.render.samples_per_pixel = 5;
    ps.pass_samples = 3;
    Film film;
    RenderStats first = render_progressive(scene, camera, progressive, film, ps);
    EXPECT_EQ(first.training_passes, 5);
    ps.render.samples_per_pixel = 8;
    (void)render_progressive(scene, camera, progressive, film, ps);
    EXPECT_TRUE(same_bits(image, resolve(film)));
}

// Guiding off (the default) is the unguided integrator: no training pass, no tree, and the
// same image as a PathTracer that never heard of guiding settings.
TEST(Guiding, OffChangesNothing) {
    Scene scene;
    build_lamp_room(scene);
    PathTracerSettings off = guided_settings();
    off.guiding.enabled = false;
    PathTracer a(off), b(PathTracerSettings{5, false});
    RenderSettings rs;
    rs.samples_per_pixel = 4;
    RenderStats stats;
    const Image ia = render(scene, Camera(lamp_room_camera(16)), a, rs, &stats);
    EXPECT_EQ(stats.training_passes, 0);
    EXPECT_EQ(a.guiding_leaf_count(), 0u);
    EXPECT_TRUE(same_bits(ia, render(scene, Camera(lamp_room_camera(16)), b, rs)));
}

}  // namespace
}  // namespace librt
