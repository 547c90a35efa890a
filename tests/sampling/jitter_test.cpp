#include "sampling/chi_square.h"

#include <librt/sampling/jitter.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace librt;

namespace {

/// Sample moments of both components of n draws of a 2D jitter.
struct Moments {
    double mean_x = 0, mean_y = 0, var_x = 0, var_y = 0, corr = 0;
};

template <typename Jitter>
Moments moments(Jitter jitter, std::uint64_t seed, int n) {
    Pcg32 rng(seed, 5u);
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int i = 0; i < n; ++i) {
        const glm::vec2 p = jitter(rng.next_vec2());
        sx += p.x;
        sy += p.y;
        sxx += double(p.x) * p.x;
        syy += double(p.y) * p.y;
        sxy += double(p.x) * p.y;
    }
    Moments m;
    m.mean_x = sx / n;
    m.mean_y = sy / n;
    m.var_x = sxx / n - m.mean_x * m.mean_x;
    m.var_y = syy / n - m.mean_y * m.mean_y;
    m.corr = (sxy / n - m.mean_x * m.mean_y) / std::sqrt(m.var_x * m.var_y);
    return m;
}

/// Checks mean 0 and standard deviation sigma for both components: the mean of n
/// normals has sd sigma / sqrt(n), the sample variance sd sqrt(2 / n) sigma^2.
void expect_gaussian(const Moments& m, double sigma, int n) {
    const double mean_tol = 5.0 * sigma / std::sqrt(n);
    const double var_tol = 5.0 * std::sqrt(2.0 / n) * sigma * sigma;
    EXPECT_NEAR(m.mean_x, 0.0, mean_tol);
    EXPECT_NEAR(m.mean_y, 0.0, mean_tol);
    EXPECT_NEAR(m.var_x, sigma * sigma, var_tol);
    EXPECT_NEAR(m.var_y, sigma * sigma, var_tol);
    EXPECT_NEAR(m.corr, 0.0, 5.0 / std::sqrt(n));
}

constexpr int kN = 200'000;

}  // namespace

TEST(Jitter, BoxMullerIsTheReportFormula) {
    // r2 = e^-1/2 gives radius sqrt(-2 ln r2) = 1; r1 = 1/4 gives angle pi/2.
    const glm::vec2 z = box_muller({0.25f, std::exp(-0.5f)});
    EXPECT_NEAR(z.x, 0.0f, 1e-6f);
    EXPECT_NEAR(z.y, 1.0f, 1e-6f);
}

TEST(Jitter, BoxMullerGivesStandardNormals) {
    expect_gaussian(moments([](glm::vec2 u) { return box_muller(u); }, 1, kN), 1.0, kN);
}

TEST(Jitter, BoxMullerMatchesNormalCdf) {
    // Chi-square of x against the standard normal: 40 bins on [-4, 4] plus both tails.
    constexpr int bins = 40;
    constexpr double lo = -4.0, hi = 4.0, width = (hi - lo) / bins;
    const auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
    std::vector<double> observed(bins + 2, 0.0), expected(bins + 2, 0.0);
    Pcg32 rng(2u, 5u);
    for (int i = 0; i < kN; ++i) {
        const double x = box_muller(rng.next_vec2()).x;
        const int cell = x < lo ? 0 : x >= hi ? bins + 1 : 1 + static_cast<int>((x - lo) / width);
        observed[static_cast<std::size_t>(std::min(cell, bins + 1))] += 1.0;
    }
    expected[0] = kN * cdf(lo);
    expected[bins + 1] = kN * (1.0 - cdf(hi));
    for (int b = 0; b < bins; ++b) {
        expected[static_cast<std::size_t>(b + 1)] =
            kN * (cdf(lo + (b + 1) * width) - cdf(lo + b * width));
    }
    const auto r = librt::testing::chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.summary();
    EXPECT_GE(r.p_value, 0.01) << r.summary();
}

TEST(Jitter, PixelJitterHasSigmaOneHalfByDefault) {
    expect_gaussian(moments([](glm::vec2 u) { return gaussian_pixel_jitter(u); }, 3, kN), 0.5, kN);
    expect_gaussian(moments([](glm::vec2 u) { return gaussian_pixel_jitter(u, 0.25f); }, 4, kN),
                    0.25, kN);
}

TEST(Jitter, LensJitterHasTheGivenSigma) {
    expect_gaussian(moments([](glm::vec2 u) { return gaussian_lens_jitter(u, 1.0f); }, 5, kN), 1.0,
                    kN);
    expect_gaussian(moments([](glm::vec2 u) { return gaussian_lens_jitter(u, 3.0f); }, 6, kN), 3.0,
                    kN);
}

TEST(Jitter, ExtremeSamplesStayFinite) {
    const float top = 1.0f - 0x1p-24f;  // the largest next_float()
    for (const glm::vec2 u :
         {glm::vec2(0.0f, 0.0f), glm::vec2(top, top), glm::vec2(0.5f, 0.0f), glm::vec2(top, 0.0f),
          glm::vec2(0.0f, top), glm::vec2(0.3f, 1.0f), glm::vec2(0.3f, 1.5f)}) {
        for (const glm::vec2 z : {box_muller(u), gaussian_pixel_jitter(u),
                                  gaussian_lens_jitter(u, 1.0f), disk_lens_jitter(u, 2.0f)}) {
            EXPECT_TRUE(std::isfinite(z.x) && std::isfinite(z.y))
                << "u = (" << u.x << ", " << u.y << ") -> (" << z.x << ", " << z.y << ")";
        }
    }
    // u2 = 0 is clamped to the smallest normal float: radius sqrt(-2 ln FLT_MIN) ~ 13.2.
    EXPECT_NEAR(glm::length(box_muller({0.0f, 0.0f})), 13.2f, 0.05f);
}

TEST(Jitter, DiskLensJitterIsUniformOnTheDisk) {
    // Radius of a uniform point on a disk of radius R: mean 2R/3, variance R^2/18.
    const float radius = 0.75f;
    Pcg32 rng(7u, 5u);
    double sum = 0.0;
    for (int i = 0; i < kN; ++i) {
        const float rho = glm::length(disk_lens_jitter(rng.next_vec2(), radius));
        ASSERT_LE(rho, radius * (1.0f + 1e-6f));
        sum += rho;
    }
    const double tol = 5.0 * std::sqrt(radius * radius / 18.0 / kN);
    EXPECT_NEAR(sum / kN, 2.0 * radius / 3.0, tol);
    const auto m = moments([&](glm::vec2 u) { return disk_lens_jitter(u, radius); }, 8, kN);
    EXPECT_NEAR(m.mean_x, 0.0, 5.0 * std::sqrt(radius * radius / 4.0 / kN));  // var R^2/4
}
