// relative_noise (render/renderer.h): the relative error of an image estimated from one pass,
// checked against the closed form on films of known variance; and render_progressive's
// progress reports carry it for every pass after the first, as pass_done's films give it.

#include <librt/film/film.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/light/environment_light.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace librt;

namespace {

/// Adds `count` grey samples, uniform on [0, 2] (mean 1, variance 1/3), to every pixel.
void add_samples(Film& film, int count, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 2.0);
    for (FilmPixel& p : film.pixels) {
        for (int k = 0; k < count; ++k) p.radiance += glm::dvec3(u(rng));
        p.samples += std::uint32_t(count);
        p.finite += std::uint32_t(count);
    }
}

}  // namespace

// 40000 pixels of 8 samples, then 4 more (n = 12): the standard error of each pixel's mean
// is sqrt((1/3) / 12) = 1/6 of its mean 1. Each pixel's term (n - m) d^2 / m is
// (sigma^2 / n) times about a chi-square of one degree of freedom (variance 2): the mean of
// 40000 has relative standard deviation sqrt(2 / 40000), its square root half of that.
// Allowed: 5 of those.
TEST(RelativeNoise, MatchesTheClosedFormOnFilmsOfKnownVariance) {
    std::mt19937_64 rng(12345);
    Film before(200, 200);
    add_samples(before, 8, rng);
    Film after = before;
    add_samples(after, 4, rng);
    const double want = std::sqrt((1.0 / 3.0) / 12.0);
    const double tolerance = 5.0 * 0.5 * std::sqrt(2.0 / 40000.0) * want;
    EXPECT_NEAR(relative_noise(before, after), want, tolerance);
}

TEST(RelativeNoise, ZeroForAConstantImageAndMinusOneWithoutAnEstimate) {
    Film before(4, 3), after(4, 3);
    for (FilmPixel& p : before.pixels) p = {glm::dvec3(0.5 * 2), 2, 2};
    for (FilmPixel& p : after.pixels) p = {glm::dvec3(0.5 * 5), 5, 5};
    EXPECT_EQ(relative_noise(before, after), 0.0);
    // The first pass (nothing before it), a pass that added nothing, other sizes, black.
    EXPECT_EQ(relative_noise(Film(4, 3), after), -1.0);
    EXPECT_EQ(relative_noise(after, after), -1.0);
    EXPECT_EQ(relative_noise(Film(2, 2), after), -1.0);
    Film black = after;
    for (FilmPixel& p : black.pixels) p.radiance = glm::dvec3(0.0);
    Film black_before = before;
    for (FilmPixel& p : black_before.pixels) p.radiance = glm::dvec3(0.0);
    EXPECT_EQ(relative_noise(black_before, black), -1.0);
}

// A progressive render of a lit box, one sample per pass: the report after pass 1 has no
// estimate; after every later pass it is relative_noise of the films pass_done saw before
// and after that pass, and positive (a path-traced box under a sky is noisy).
TEST(RelativeNoise, ProgressReportsItAfterEveryPassButTheFirst) {
    Scene scene;
    const std::uint32_t m = scene.add_material(Material::diffuse(glm::vec3(0.7f)));
    (void)scene.add_mesh(make_box({-1, -1, -1}, {1, 1, 1}), m);
    scene.add_environment_light(EnvironmentLight::constant(glm::vec3(1.0f)));
    scene.commit();
    CameraSettings cs;
    cs.width = 24;
    cs.height = 16;
    cs.position = {2, 3, 5};
    cs.look_at = {0, 0, 0};
    cs.vertical_fov_degrees = 50.0f;
    const Camera camera(cs);
    PathTracer pt;
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = 5;
    ps.render.threads = 2;
    std::vector<Film> films;
    std::vector<double> at_pass_end;  // the report made as each pass finished
    ps.render.progress = [&](const RenderProgress& p) {
        if (p.passes > int(at_pass_end.size())) at_pass_end.push_back(p.noise);
    };
    ps.pass_done = [&](const Film& f, std::uint32_t /*level*/) { films.push_back(f); };
    Film film;
    (void)render_progressive(scene, camera, pt, film, ps);
    ASSERT_EQ(films.size(), 5u);
    ASSERT_EQ(at_pass_end.size(), 5u);
    EXPECT_EQ(at_pass_end[0], -1.0);
    for (std::size_t k = 1; k < films.size(); ++k) {
        EXPECT_EQ(at_pass_end[k], relative_noise(films[k - 1], films[k])) << "pass " << k + 1;
        EXPECT_GT(at_pass_end[k], 0.0) << "pass " << k + 1;
    }
}
