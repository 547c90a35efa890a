// NoiseEstimate against the closed form of a film of known variance, and the noise target
// of render_progressive.

#include <librt/core/error.h>
#include <librt/render/noise_estimate.h>
#include <librt/render/renderer.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>

using namespace librt;

namespace {

// Samples uniform in [0.5, 1.5] in every channel: mean 1, variance 1/12.
constexpr double kVariance = 1.0 / 12.0;
// relMSE of a pixel mean of n such samples: (1/12) / (n (1 + 0.01)).
double expected_error(double n) { return std::sqrt(kVariance / (n * (1.0 + 0.01))); }

// Adds samples [from, to) to every pixel of `film`, each channel its own draw.
void add_samples(Film& film, std::uint32_t from, std::uint32_t to, Pcg32& rng) {
    for (FilmPixel& p : film.pixels) {
        for (std::uint32_t s = from; s < to; ++s) {
            p.radiance +=
                glm::dvec3(0.5 + rng.next_float(), 0.5 + rng.next_float(), 0.5 + rng.next_float());
        }
        p.samples = p.finite = to;
    }
}

// The estimate from the last doubling (128 + 128 samples per pixel, 64 x 64 pixels). The
// per-pixel estimates are d^2 / (1/128 + 1/128) with d nearly normal: chi^2 with one
// degree of freedom, relative spread sqrt(2); their mean over 4096 pixels spreads by
// sqrt(2 / 4096) = 2.2 %, the square root by half that, 1.1 %. The dark floor's Jensen bias
// is about 3 (1.8 %)^2 = 0.1 % at these counts. Bound: 5 sigma, 5.5 %.
TEST(NoiseEstimate, MatchesTheClosedFormOfAFilmOfKnownVariance) {
    Film film(64, 64);
    Pcg32 rng(7, 11);
    NoiseEstimate noise;
    std::uint32_t level = 0;
    for (const std::uint32_t next : {1u, 2u, 4u, 8u, 16u, 32u, 64u, 128u, 256u}) {
        add_samples(film, level, next, rng);
        level = next;
        noise.observe(film, level);
        if (level == 1) {
            EXPECT_FALSE(noise.relative_error()) << "one look is only a snapshot";
        } else {
            ASSERT_TRUE(noise.relative_error()) << "level " << level;
        }
    }
    const double expected = expected_error(256.0);
    EXPECT_NEAR(*noise.relative_error() / expected, 1.0, 0.055)
        << "estimate " << *noise.relative_error() << ", closed form " << expected;
}

// Between doublings the estimate keeps the last renewal's: it is not renewed from a
// handful of new samples.
TEST(NoiseEstimate, RenewsOnlyWhenTheLevelHasDoubled) {
    Film film(16, 16);
    Pcg32 rng(3, 5);
    NoiseEstimate noise;
    add_samples(film, 0, 8, rng);
    noise.observe(film, 8);
    add_samples(film, 8, 16, rng);
    noise.observe(film, 16);
    const double at16 = *noise.relative_error();
    add_samples(film, 16, 20, rng);
    noise.observe(film, 20);
    EXPECT_EQ(*noise.relative_error(), at16);
}

// A pixel holding the same value in every sample has no noise; a black one counts by the
// dark floor only: 0 / (0 + 0.01) = 0.
TEST(NoiseEstimate, ANoiseFreeFilmHasNoError) {
    Film film(8, 8);
    for (std::size_t i = 0; i < film.pixels.size(); ++i) {
        film.pixels[i].radiance = glm::dvec3(i % 2 == 0 ? 0.0 : 4.0);
        film.pixels[i].samples = film.pixels[i].finite = 4;
    }
    NoiseEstimate noise;
    noise.observe(film, 4);
    for (FilmPixel& p : film.pixels) {
        p.radiance *= 2.0;
        p.samples = p.finite = 8;
    }
    noise.observe(film, 8);
    ASSERT_TRUE(noise.relative_error());
    EXPECT_EQ(*noise.relative_error(), 0.0);
}

// Uniform in [0.5, 1.5] per channel, from the sampler: the closed form above.
class UniformNoise final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& /*ray*/,
                               Sampler& sampler) const override {
        return {0.5f + sampler.next_1d(), 0.5f + sampler.next_1d(), 0.5f + sampler.next_1d()};
    }
};

// The 32 x 32 camera of the render tests below.
Camera noise_camera() {
    CameraSettings cs;
    cs.width = 32;
    cs.height = 32;
    return Camera(cs);
}

// Progressive settings of `spp` samples in passes of 8, two threads, fixed seed, with
// independent samples and no adaptive sampling: the closed form is theirs (Sobol' samples
// are stratified and converge faster).
ProgressiveSettings independent_passes_of_8(int spp) {
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = spp;
    ps.render.threads = 2;
    ps.render.seed = 5;
    ps.render.sampler = SamplerKind::Independent;
    ps.render.adaptive.enabled = false;
    ps.pass_samples = 8;
    return ps;
}

// render_progressive stops at the first renewal (a doubling of the level) whose estimate
// is within the target. The target is the geometric mean of the closed-form errors at 64
// and 128 samples: 0.84 x the one, 1.19 x the other. At 32 x 32 pixels the estimate spreads
// by sqrt(2 / 1024) / 2 = 2.2 %, so each is 7 sigma or more from the target: the render
// must stop at 128 samples per pixel, not before and not after. Independent samples: the
// closed form is theirs (Sobol' samples are stratified and converge faster).
TEST(NoiseEstimate, TheNoiseTargetStopsTheRenderAtTheFirstLevelWithinIt) {
    Scene scene;
    scene.commit();
    const Camera camera = noise_camera();
    UniformNoise integrator;
    ProgressiveSettings ps = independent_passes_of_8(1024);
    const double at64 = expected_error(64.0);
    const double at128 = expected_error(128.0);
    ps.noise_target = std::sqrt(at64 * at128);  // 1.19 x at128, 0.84 x at64
    Film film;
    const RenderStats stats = render_progressive(scene, camera, integrator, film, ps);
    EXPECT_TRUE(stats.noise_target_reached);
    EXPECT_EQ(stats.samples_per_pixel, 128u);
    EXPECT_NEAR(stats.noise / at128, 1.0, 0.11);
    EXPECT_EQ(film.at(3, 4).samples, 128u);
}

// The progress reports show the number a noise target stops on, so a user reads the target
// to give off the progress display. Without a target, the reports carry NoiseEstimate's
// estimate: -1 until the level has doubled once (16 samples: passes of 8), then one value
// per doubling, about the closed form (the bounds of the test above). Given a target equal
// to the value shown at 128 samples, the render stops exactly there (the values shown at
// 16, 32 and 64 are above it: each doubling divides the closed form by sqrt(2), where
// the estimate spreads by 2.2 %) and its RenderStats::noise is that value, bit for bit; its
// reports are the ones shown without a target.
TEST(NoiseEstimate, TheProgressShowsWhatTheNoiseTargetStopsOn) {
    Scene scene;
    scene.commit();
    const Camera camera = noise_camera();
    UniformNoise integrator;
    ProgressiveSettings ps = independent_passes_of_8(256);
    // The value shown once every pixel holds `samples_per_pixel` samples (the reports of the
    // next pass repeat it).
    std::map<std::uint32_t, double> shown;
    const auto record = [&shown](const RenderProgress& p) { shown[p.samples_per_pixel] = p.noise; };
    ps.render.progress = record;
    Film film;
    const RenderStats free_run = render_progressive(scene, camera, integrator, film, ps);
    EXPECT_FALSE(free_run.noise_target_reached);
    EXPECT_EQ(free_run.samples_per_pixel, 256u);
    EXPECT_EQ(shown[8], -1.0);
    for (const std::uint32_t level : {16u, 32u, 64u, 128u, 256u}) {
        EXPECT_NEAR(shown[level] / expected_error(level), 1.0, 0.11) << level;
    }
    EXPECT_EQ(shown[24], shown[16]);  // renewed at doublings only
    EXPECT_EQ(free_run.noise, shown[256]);

    const std::map<std::uint32_t, double> without_target = shown;
    shown.clear();
    ps.noise_target = without_target.at(128);
    film = Film();
    const RenderStats stopped = render_progressive(scene, camera, integrator, film, ps);
    EXPECT_TRUE(stopped.noise_target_reached);
    EXPECT_EQ(stopped.samples_per_pixel, 128u);
    EXPECT_EQ(stopped.noise, ps.noise_target);
    EXPECT_EQ(shown.rbegin()->first, 128u);
    for (const auto& [level, noise] : shown) {
        // Level 0: reports during the first pass, made by the clock, in one run or both.
        if (level == 0) continue;
        ASSERT_TRUE(without_target.count(level)) << level;
        EXPECT_EQ(noise, without_target.at(level)) << level;
    }
}

TEST(NoiseEstimate, ANoiseTargetOutsideItsRangeIsRefused) {
    ProgressiveSettings ps;
    for (const double bad : {-0.1, 1.5, std::nan("")}) {
        ps.noise_target = bad;
        EXPECT_THROW(validate(ps), Error) << bad;
    }
    ps.noise_target = 0.02;
    EXPECT_NO_THROW(validate(ps));
}

}  // namespace
