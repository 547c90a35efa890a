// Keeping path guiding's training passes in the image (GuidingSettings::
// keep_training_samples): render() weights each pass and the image by the inverse of its
// variance. On an integrator whose passes have known noise, the combination is unbiased and
// reaches the optimal inverse-variance combination's variance; a guided render of the
// report's room that keeps its passes agrees with the unguided one (whole image and 4 x 4
// blocks, standard errors from independent replicates).

#include "integrator_test_util.h"

#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace librt {
namespace {

/// Radiance mu plus zero-mean uniform noise whose standard deviation depends on the pass:
/// kSigma[k] in training pass k, kSigma[4] in the image.
class NoisyPasses final : public Integrator {
public:
    static constexpr std::array<double, 5> kSigma{8.0, 2.0, 1.5, 1.2, 1.0};
    static constexpr double kMu = 2.0;

    std::uint32_t begin_training_pass(int pass) override {
        stage_ = pass < 4 ? pass : 4;
        return pass < 4 ? std::uint32_t{1} << std::uint32_t(pass) : 0u;
    }
    bool keeps_training_samples() const override { return keep_; }
    glm::vec3 li(const Scene& /*scene*/, const Ray& /*ray*/, Sampler& sampler) const override {
        // Uniform on [-sqrt(3) sigma, sqrt(3) sigma]: variance sigma^2.
        const double u = sampler.next_1d();
        return glm::vec3(
            float(kMu + kSigma[std::size_t(stage_)] * std::sqrt(3.0) * (2.0 * u - 1.0)));
    }
    void set_keep(bool keep) { keep_ = keep; }

private:
    int stage_ = 4;
    bool keep_ = true;
};

/// Mean and unbiased variance of the red channel over the image's pixels.
std::array<double, 2> pixel_mean_and_variance(const Image& image) {
    double s = 0.0, s2 = 0.0;
    for (const glm::vec3& p : image.pixels) {
        s += p.x;
        s2 += double(p.x) * p.x;
    }
    const double n = double(image.pixels.size());
    const double mean = s / n;
    return {mean, (s2 - n * mean * mean) / (n - 1.0)};
}

// The combination is unbiased and as good as inverse-variance weighting with the true
// variances: its pixel variance is 1 / sum_k (n_k / sigma_k^2) over the kept passes (1, 2:
// 2, 4 and 8 samples; pass 0 has one sample, no variance estimate, and is dropped) and the
// image's 16 samples. 4096 independent pixels: the pixels' variance has a relative standard
// error of sqrt(2 / 4095) = 2.2%, so 5 of them is 11%; the mean is checked to 5 standard
// errors.
TEST(GuidingCombination, InverseVarianceWeightsAreUnbiasedAndOptimal) {
    Scene scene;
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 64;
    const Camera camera(cs);
    RenderSettings rs;
    rs.samples_per_pixel = 16;
    rs.threads = 2;
    rs.seed = 5;
    // Independent samples, 16 in every pixel: the variances above are theirs (and kept
    // passes join an image of equal counts only).
    rs.sampler = SamplerKind::Independent;
    rs.adaptive.enabled = false;
    NoisyPasses integrator;
    const Image combined = render(scene, camera, integrator, rs);
    double inverse = 16.0 / (NoisyPasses::kSigma[4] * NoisyPasses::kSigma[4]);
    for (int k = 1; k < 4; ++k)
        inverse += double(1 << k) /
                   (NoisyPasses::kSigma[std::size_t(k)] * NoisyPasses::kSigma[std::size_t(k)]);
    const double optimal = 1.0 / inverse;
    const auto [mean, variance] = pixel_mean_and_variance(combined);
    const double n = double(combined.pixels.size());
    EXPECT_NEAR(mean, NoisyPasses::kMu, 5.0 * std::sqrt(variance / n));
    const double rel = 5.0 * std::sqrt(2.0 / (n - 1.0));
    EXPECT_GT(variance, optimal * (1.0 - rel)) << "optimal " << optimal;
    EXPECT_LT(variance, optimal * (1.0 + rel)) << "optimal " << optimal;

    // Without keeping, the image alone: variance sigma_4^2 / 16, higher than the
    // combination's by more than the tolerance.
    integrator.set_keep(false);
    const auto [mean_alone, variance_alone] =
        pixel_mean_and_variance(render(scene, camera, integrator, rs));
    const double alone = NoisyPasses::kSigma[4] * NoisyPasses::kSigma[4] / 16.0;
    EXPECT_NEAR(variance_alone, alone, rel * alone);
    EXPECT_GT(alone, optimal * (1.0 + 2.0 * rel));
    EXPECT_NEAR(mean_alone, NoisyPasses::kMu, 5.0 * std::sqrt(variance_alone / n));
}

// render_progressive keeps the passes too (its final frame): in passes of 3 samples its
// image is render()'s bit for bit, so unbiased and optimal as above, checked again here.
TEST(GuidingCombination, ProgressiveKeepsThePassesAsRenderDoes) {
    Scene scene;
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 64;
    const Camera camera(cs);
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = 16;
    ps.render.threads = 2;
    ps.render.seed = 5;
    ps.render.sampler = SamplerKind::Independent;  // as the test above
    ps.render.adaptive.enabled = false;
    ps.pass_samples = 3;
    NoisyPasses integrator;
    Film film;
    Image image;
    (void)render_progressive(scene, camera, integrator, film, ps, &image);
    NoisyPasses one_shot;
    const Image expected = render(scene, camera, one_shot, ps.render);
    ASSERT_EQ(image.pixels.size(), expected.pixels.size());
    EXPECT_EQ(std::memcmp(image.pixels.data(), expected.pixels.data(),
                          image.pixels.size() * sizeof(glm::vec3)),
              0);
    double inverse = 16.0 / (NoisyPasses::kSigma[4] * NoisyPasses::kSigma[4]);
    for (int k = 1; k < 4; ++k)
        inverse += double(1 << k) /
                   (NoisyPasses::kSigma[std::size_t(k)] * NoisyPasses::kSigma[std::size_t(k)]);
    const double optimal = 1.0 / inverse;
    const auto [mean, variance] = pixel_mean_and_variance(image);
    const double n = double(image.pixels.size());
    EXPECT_NEAR(mean, NoisyPasses::kMu, 5.0 * std::sqrt(variance / n));
    const double rel = 5.0 * std::sqrt(2.0 / (n - 1.0));
    EXPECT_NEAR(variance, optimal, rel * optimal);
    // The film alone holds the image's 16 samples: variance sigma_4^2 / 16.
    const auto [film_mean, film_variance] = pixel_mean_and_variance(resolve(film));
    const double alone = NoisyPasses::kSigma[4] * NoisyPasses::kSigma[4] / 16.0;
    EXPECT_NEAR(film_variance, alone, rel * alone);
    EXPECT_NEAR(film_mean, NoisyPasses::kMu, 5.0 * std::sqrt(film_variance / n));
}

/// Means of the whole image (index 16) and of its 4 x 4 blocks (0..15), red, green, blue.
std::vector<glm::dvec3> block_means(const Image& image) {
    std::vector<glm::dvec3> out(17, glm::dvec3(0.0));
    const int bw = image.width / 4, bh = image.height / 4;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const glm::dvec3 v(image.at(x, y));
            out[std::size_t((y / bh) * 4 + x / bw)] += v / double(bw * bh);
            out[16] += v / double(image.width * image.height);
        }
    return out;
}

/// Mean and squared standard error of each block over replicate renders.
struct Replicates {
    std::vector<glm::dvec3> mean, se2;
};

Replicates replicate(const Scene& scene, const Camera& camera, bool guided, int spp, int count,
                     std::uint64_t seed0) {
    std::vector<std::vector<glm::dvec3>> runs;
    for (int r = 0; r < count; ++r) {
        PathTracerSettings s{5, false};
        s.guiding.enabled = guided;
        s.guiding.keep_training_samples = true;
        s.guiding.spatial_threshold = 300;  // small images: let the spatial tree split
        PathTracer integrator(s);
        RenderSettings rs;
        rs.samples_per_pixel = spp;
        rs.threads = 2;
        rs.seed = seed0 + std::uint64_t(r);
        runs.push_back(block_means(render(scene, camera, integrator, rs)));
    }
    Replicates out{std::vector<glm::dvec3>(17, glm::dvec3(0.0)),
                   std::vector<glm::dvec3>(17, glm::dvec3(0.0))};
    for (std::size_t b = 0; b < 17; ++b) {
        for (const auto& run : runs) out.mean[b] += run[b] / double(count);
        for (const auto& run : runs) {
            const glm::dvec3 d = run[b] - out.mean[b];
            out.se2[b] += d * d / (double(count - 1) * double(count));
        }
    }
    return out;
}

// Unbiased: 24 guided renders that keep their training passes against 24 unguided ones,
// each block's mean within 5 standard errors (estimated from the replicates: Student's t
// with 46 degrees of freedom, 5 of them a false alarm about once in 10^5 per comparison).
TEST(GuidingCombination, KeptPassesAgreeWithUnguidedOnTheReportRoom) {
    Scene scene;
    testing::add_room(scene);
    scene.add_sphere_light({{{-10, 20, 40}, 10}, glm::vec3(50.0f)});
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 16;
    const Camera camera(cs);
    const int count = 24;
    const Replicates g = replicate(scene, camera, true, 32, count, 1000);
    const Replicates u = replicate(scene, camera, false, 32, count, 2000);
    for (std::size_t b = 0; b < 17; ++b)
        for (int c = 0; c < 3; ++c) {
            const double tol = 5.0 * std::sqrt(g.se2[b][c] + u.se2[b][c]);
            EXPECT_LE(std::fabs(g.mean[b][c] - u.mean[b][c]), tol)
                << (b == 16 ? std::string("whole image") : "block " + std::to_string(b))
                << " channel " << c << ": " << g.mean[b][c] << " vs " << u.mean[b][c];
        }
    // Power: the whole image's difference is resolved to 2% of its value.
    for (int c = 0; c < 3; ++c)
        EXPECT_LT(std::sqrt(g.se2[16][c] + u.se2[16][c]), 0.02 * u.mean[16][c]);
}

}  // namespace
}  // namespace librt
