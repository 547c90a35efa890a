#include "sampling/chi_square.h"

#include <librt/core/error.h>
#include <librt/sampling/filter.h>
#include <librt/sampling/jitter.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace librt;

namespace {

FilterSettings make(FilterKind kind, float radius, float sigma = 0.5f, float b = 1.0f / 3.0f,
                    float c = 1.0f / 3.0f) {
    FilterSettings s;
    s.kind = kind;
    s.radius = radius;
    s.sigma = sigma;
    s.mitchell_b = b;
    s.mitchell_c = c;
    return s;
}

// The filters under test, including non-default radii and Mitchell parameters.
std::vector<FilterSettings> all_filters() {
    return {make(FilterKind::Box, 0.5f),
            make(FilterKind::Box, 1.3f),
            make(FilterKind::Tent, 1.0f),
            make(FilterKind::Tent, 2.2f),
            make(FilterKind::Gaussian, 1.5f, 0.5f),
            make(FilterKind::Gaussian, 2.5f, 1.0f),
            make(FilterKind::Mitchell, 2.0f),
            make(FilterKind::Mitchell, 1.5f, 0.5f, 0.0f, 0.5f),  // Catmull-Rom: deep lobes
            make(FilterKind::BlackmanHarris, 1.5f),
            make(FilterKind::BlackmanHarris, 3.0f),
            make(FilterKind::Smallpt, 0.75f),
            make(FilterKind::Smallpt, 1.5f)};
}

std::string name(const FilterSettings& s) {
    static const char* names[] = {"box",    "tent", "gaussian", "mitchell", "blackman-harris",
                                  "smallpt"};
    return std::string(names[static_cast<int>(s.kind)]) + " r=" + std::to_string(s.radius);
}

// integral of g over [a, b] by composite Simpson with 400 intervals, in double.
template <typename G>
double simpson(G g, double a, double b) {
    constexpr int n = 400;
    const double h = (b - a) / n;
    double sum = g(a) + g(b);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * g(a + i * h);
    return sum * h / 3.0;
}

}  // namespace

TEST(PixelFilter, OffsetsFollowTheNormalisedAbsoluteShape) {
    // 2D chi-square: a bins x bins histogram of sampled offsets over [-r, r]^2 against
    // n * (integral of |f| over the bin) / (integral of |f|), by the test's own quadrature
    // of evaluate_1d (f is separable, so the 2D bin mass is a product of 1D masses).
    constexpr int n = 200000, bins = 24;
    for (const FilterSettings& settings : all_filters()) {
        const PixelFilter filter(settings);
        const double r = settings.radius;
        std::vector<double> mass(bins);
        double total = 0.0;
        for (int i = 0; i < bins; ++i) {
            const double a = -r + 2.0 * r * i / bins, b = a + 2.0 * r / bins;
            mass[i] =
                simpson([&](double x) { return std::abs(filter.evaluate_1d(float(x))); }, a, b);
            total += mass[i];
        }
        std::vector<double> expected(bins * bins), observed(bins * bins, 0.0);
        for (int i = 0; i < bins; ++i) {
            for (int j = 0; j < bins; ++j)
                expected[i * bins + j] = n * mass[i] * mass[j] / (total * total);
        }
        Pcg32 rng(2024, 17);
        for (int k = 0; k < n; ++k) {
            const FilterSample s = filter.sample(rng.next_vec2());
            ASSERT_LE(std::abs(s.offset.x), settings.radius) << name(settings);
            ASSERT_LE(std::abs(s.offset.y), settings.radius) << name(settings);
            const auto cell = [&](float v) {
                return std::min(bins - 1, static_cast<int>((v + r) / (2.0 * r) * bins));
            };
            observed[cell(s.offset.x) * bins + cell(s.offset.y)] += 1.0;
        }
        const auto result = librt::testing::chi_square_test(observed, expected);
        EXPECT_TRUE(result.error.empty()) << name(settings) << ": " << result.summary();
        EXPECT_GE(result.p_value, 0.01) << name(settings) << ": " << result.summary();
    }
}

TEST(PixelFilter, WeightsMakeThePlainMeanTheNormalisedFilter) {
    // E[weight * g(offset)] must be integral f g / integral f: the pixel's plain mean of
    // weighted samples is the normalised filter's estimate. g = 1 and a smooth g, checked
    // within 4 standard errors; the exact side by quadrature of evaluate_1d.
    constexpr int n = 200000;
    const auto g = [](double x, double y) { return 1.0 + x * x + 0.5 * y; };
    for (const FilterSettings& settings : all_filters()) {
        const PixelFilter filter(settings);
        const double r = settings.radius;
        const auto f = [&](double x) { return double(filter.evaluate_1d(float(x))); };
        // g is a sum of separable terms: int f(x) f(y) g = F0 F0 + F2 F0 + 0.5 F0 F1.
        const double f0 = simpson(f, -r, r);
        const double f1 = simpson([&](double x) { return x * f(x); }, -r, r);
        const double f2 = simpson([&](double x) { return x * x * f(x); }, -r, r);
        const double exact_g = (f0 * f0 + f2 * f0 + 0.5 * f0 * f1) / (f0 * f0);
        Pcg32 rng(99, 3);
        double sum_w = 0, sum_ww = 0, sum_wg = 0, sum_wgwg = 0;
        for (int k = 0; k < n; ++k) {
            const FilterSample s = filter.sample(rng.next_vec2());
            // The sign of the weight is the sign of f where the offset landed.
            const float value = filter.evaluate(s.offset);
            if (std::abs(value) > 1e-4f) {
                ASSERT_GT(s.weight * value, 0.0f) << name(settings);
            }
            const double wg = s.weight * g(s.offset.x, s.offset.y);
            sum_w += s.weight;
            sum_ww += double(s.weight) * s.weight;
            sum_wg += wg;
            sum_wgwg += wg * wg;
        }
        const double mean_w = sum_w / n, mean_wg = sum_wg / n;
        const double se_w = std::sqrt(std::max(0.0, sum_ww / n - mean_w * mean_w) / n);
        const double se_wg = std::sqrt((sum_wgwg / n - mean_wg * mean_wg) / n);
        EXPECT_NEAR(mean_w, 1.0, 4.0 * se_w + 1e-6) << name(settings);
        EXPECT_NEAR(mean_wg, exact_g, 4.0 * se_wg) << name(settings);
        if (settings.kind != FilterKind::Mitchell) {
            EXPECT_EQ(sum_ww, double(n));  // every weight is 1
        }
    }
}

TEST(PixelFilter, InversionIsMonotoneSoStratifiedInputStaysStratified) {
    for (const FilterSettings& settings : all_filters()) {
        const PixelFilter filter(settings);
        float previous = -std::numeric_limits<float>::infinity();
        for (int i = 0; i < 4096; ++i) {
            const float u = (static_cast<float>(i) + 0.5f) / 4096.0f;
            const FilterSample s = filter.sample({u, 0.5f});
            EXPECT_GE(s.offset.x, previous) << name(settings) << " u " << u;
            previous = s.offset.x;
        }
        // The offsets cover the support: the extremes come close to +-radius.
        EXPECT_LT(filter.sample({0.0f, 0.5f}).offset.x, -0.8f * settings.radius) << name(settings);
        EXPECT_GT(filter.sample({0.99999f, 0.5f}).offset.x, 0.8f * settings.radius)
            << name(settings);
    }
}

TEST(PixelFilter, UntruncatedGaussianIsTheReportsJitterBitForBit) {
    FilterSettings s = make(FilterKind::Gaussian, std::numeric_limits<float>::infinity(), 0.5f);
    const PixelFilter filter(s);
    Pcg32 rng(1, 2);
    for (int i = 0; i < 10000; ++i) {
        const glm::vec2 u = rng.next_vec2();
        const FilterSample sample = filter.sample(u);
        EXPECT_EQ(sample.offset, gaussian_pixel_jitter(u, 0.5f));
        EXPECT_EQ(sample.weight, 1.0f);
    }
}

TEST(PixelFilter, DefaultsAndShapes) {
    EXPECT_EQ(default_filter_settings(FilterKind::Tent).radius, 1.0f);
    EXPECT_EQ(default_filter_settings(FilterKind::Mitchell).radius, 2.0f);
    // Closed-form values: the tent's slope, Mitchell's f(0) = (6 - 2B) / 6 and its zero at
    // the radius, Blackman-Harris's a0 + a1 + a2 + a3 = 1 at the centre.
    const PixelFilter tent(make(FilterKind::Tent, 2.0f));
    EXPECT_FLOAT_EQ(tent.evaluate_1d(0.5f), 0.75f);
    EXPECT_EQ(tent.evaluate_1d(2.5f), 0.0f);
    const PixelFilter mitchell(make(FilterKind::Mitchell, 2.0f));
    EXPECT_FLOAT_EQ(mitchell.evaluate_1d(0.0f), (6.0f - 2.0f / 3.0f) / 6.0f);
    EXPECT_NEAR(mitchell.evaluate_1d(2.0f), 0.0f, 1e-6f);
    EXPECT_LT(mitchell.evaluate_1d(1.5f), 0.0f);  // the negative lobe
    const PixelFilter bh(make(FilterKind::BlackmanHarris, 1.5f));
    EXPECT_NEAR(bh.evaluate_1d(0.0f), 1.0f, 1e-6f);
    EXPECT_NEAR(bh.evaluate_1d(1.5f), 0.35875 - 0.48829 + 0.14128 - 0.01168, 1e-6);
}

namespace {

// smallpt's sub-pixel offset from the pixel centre, written from its radiance loop: a
// sub-pixel s in {0, 1} with probability 1/2 each, then a tent d on [-1, 1], at
// (s + 0.5 + d) / 2 - 0.5. Two steps, as smallpt draws it (not the filter's inversion).
float smallpt_offset(float u_subpixel, float u_tent) {
    const float s = u_subpixel < 0.5f ? 0.0f : 1.0f;
    const float r = 2.0f * u_tent;
    const float d = r < 1.0f ? std::sqrt(r) - 1.0f : 1.0f - std::sqrt(2.0f - r);
    return (s + 0.5f + d) / 2.0f - 0.5f;
}

// The trapezoid's CDF in closed form: the mean of the CDFs of two tents of half-width
// 0.5 centred at -+0.25, each (1 + t / 0.5)^2 / 2 left of its centre and 1 minus that
// mirrored right of it.
double smallpt_cdf(double x) {
    const auto tent_cdf = [](double t) {
        if (t <= -0.5) return 0.0;
        if (t >= 0.5) return 1.0;
        const double a = 1.0 - std::abs(t) / 0.5;  // 1 at the centre, 0 at the ends
        return t < 0.0 ? 0.5 * a * a : 1.0 - 0.5 * a * a;
    };
    return 0.5 * (tent_cdf(x + 0.25) + tent_cdf(x - 0.25));
}

}  // namespace

TEST(PixelFilter, SmallptOffsetsFollowSmallptsSubPixelTents) {
    // 1D chi-square over 60 bins of [-0.75, 0.75] against the closed-form CDF, for the
    // filter's offsets (both axes) and, checking the derivation in filter.cpp, for smallpt's
    // own two-step draw; p >= 0.01 at 200000 samples fails for a shape wrong by ~1 %.
    constexpr int n = 200000, bins = 60;
    std::vector<double> expected(bins);
    for (int i = 0; i < bins; ++i) {
        const double a = -0.75 + 1.5 * i / bins, b = a + 1.5 / bins;
        expected[i] = n * (smallpt_cdf(b) - smallpt_cdf(a));
    }
    const auto bin_of = [](float v) {
        return std::clamp(static_cast<int>((v + 0.75f) / 1.5f * bins), 0, bins - 1);
    };
    const PixelFilter filter(default_filter_settings(FilterKind::Smallpt));
    EXPECT_EQ(filter.settings().radius, 0.75f);
    std::vector<double> x_counts(bins, 0.0), y_counts(bins, 0.0), smallpt_counts(bins, 0.0);
    Pcg32 rng(41, 7);
    for (int k = 0; k < n; ++k) {
        const FilterSample s = filter.sample(rng.next_vec2());
        ASSERT_LE(std::abs(s.offset.x), 0.75f);
        ASSERT_LE(std::abs(s.offset.y), 0.75f);
        EXPECT_EQ(s.weight, 1.0f);
        x_counts[bin_of(s.offset.x)] += 1.0;
        y_counts[bin_of(s.offset.y)] += 1.0;
        const glm::vec2 u = rng.next_vec2();
        smallpt_counts[bin_of(smallpt_offset(u.x, u.y))] += 1.0;
    }
    for (const auto* counts : {&x_counts, &y_counts, &smallpt_counts}) {
        const auto result = librt::testing::chi_square_test(*counts, expected);
        EXPECT_TRUE(result.error.empty()) << result.summary();
        EXPECT_GE(result.p_value, 0.01) << result.summary();
    }
    // A plain tent of radius 0.75 (the nearest of the other shapes) fails the same test:
    // the test can tell the shapes apart.
    const PixelFilter tent(make(FilterKind::Tent, 0.75f));
    std::vector<double> tent_counts(bins, 0.0);
    for (int k = 0; k < n; ++k) tent_counts[bin_of(tent.sample(rng.next_vec2()).offset.x)] += 1.0;
    EXPECT_LT(librt::testing::chi_square_test(tent_counts, expected).p_value, 1e-6);
}

TEST(PixelFilter, SmallptDensityIsFlatThenLinearAndIntegratesToOne) {
    const PixelFilter filter(default_filter_settings(FilterKind::Smallpt));
    // At smallpt's radius 0.75, f is the normalised density: 1 on |x| <= 0.25, then
    // 1.5 - 2 |x| down to 0 at 0.75, 0 beyond.
    for (const float x : {0.0f, 0.1f, -0.2f, 0.25f, -0.25f}) {
        EXPECT_EQ(filter.evaluate_1d(x), 1.0f) << x;
    }
    for (const float x : {0.3f, -0.5f, 0.6f, 0.7f}) {
        EXPECT_NEAR(filter.evaluate_1d(x), 1.5f - 2.0f * std::abs(x), 1e-6f) << x;
    }
    for (const float x : {0.75f, -0.75f, 0.8f, -2.0f, 100.0f}) {
        EXPECT_EQ(filter.evaluate_1d(x), 0.0f) << x;
    }
    // The density integrates to 1 (Simpson on the three linear pieces is exact).
    const auto f = [&](double x) { return filter.evaluate_1d_precise(x); };
    const double total =
        simpson(f, -0.75, -0.25) + simpson(f, -0.25, 0.25) + simpson(f, 0.25, 0.75);
    EXPECT_NEAR(total, 1.0, 1e-12);
    // Its CDF is the closed form's at every quarter of the support.
    for (double x = -0.75; x <= 0.75; x += 0.125) {
        EXPECT_NEAR(simpson(f, -0.75, std::min(x, -0.25)) +
                        (x > -0.25 ? simpson(f, -0.25, std::min(x, 0.25)) : 0.0) +
                        (x > 0.25 ? simpson(f, 0.25, x) : 0.0),
                    smallpt_cdf(x), 1e-12)
            << x;
    }
    // Stretched to radius 1.5: flat to 0.5, twice as wide, the same shape.
    const PixelFilter wide(make(FilterKind::Smallpt, 1.5f));
    EXPECT_EQ(wide.evaluate_1d(0.5f), 1.0f);
    EXPECT_NEAR(wide.evaluate_1d(1.0f), filter.evaluate_1d(0.5f), 1e-6f);
    EXPECT_EQ(wide.evaluate_1d(1.5f), 0.0f);
}

TEST(PixelFilter, BadSettingsNameTheParameter) {
    const auto expect_rejects = [](const FilterSettings& s, const std::string& what) {
        try {
            const PixelFilter filter(s);
            ADD_FAILURE() << "accepted " << what;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    expect_rejects(make(FilterKind::Box, 0.0f), "radius = 0");
    expect_rejects(make(FilterKind::Tent, -1.0f), "radius = -1");
    expect_rejects(make(FilterKind::Box, std::numeric_limits<float>::infinity()), "radius = inf");
    expect_rejects(make(FilterKind::Mitchell, NAN), "radius");
    expect_rejects(make(FilterKind::Gaussian, 1.0f, 0.0f), "sigma = 0");
    expect_rejects(make(FilterKind::Gaussian, 1.0f, NAN), "sigma");
    expect_rejects(make(FilterKind::Mitchell, 2.0f, 0.5f, NAN), "mitchell_b");
    expect_rejects(make(FilterKind::Mitchell, 2.0f, 0.5f, 0.3f, INFINITY), "mitchell_c");
    expect_rejects(make(FilterKind::Smallpt, 0.0f), "radius = 0");
    FilterSettings bad_kind;
    bad_kind.kind = static_cast<FilterKind>(17);
    expect_rejects(bad_kind, "kind = 17");
}
