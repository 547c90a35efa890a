#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>
#include <librt/sampling/sobol.h>
#include <librt/sampling/warp.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

using namespace librt;

namespace {

// Whether n = 2^k points form a (0, k, 2)-net in base 2: every elementary interval of
// area 1/n, [i / 2^a, (i + 1) / 2^a) x [j / 2^(k-a), (j + 1) / 2^(k-a)) for every
// a = 0..k, holds exactly one point.
::testing::AssertionResult is_02_net(const std::vector<glm::vec2>& points, int k) {
    const std::size_t n = std::size_t{1} << k;
    if (points.size() < n) return ::testing::AssertionFailure() << "too few points";
    for (int a = 0; a <= k; ++a) {
        const float sx = std::ldexp(1.0f, a), sy = std::ldexp(1.0f, k - a);
        std::vector<int> count(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const auto cx = static_cast<std::size_t>(points[i].x * sx);  // exact: power of 2
            const auto cy = static_cast<std::size_t>(points[i].y * sy);
            const std::size_t cell = cx * (std::size_t{1} << (k - a)) + cy;
            if (cell >= n || ++count[cell] > 1) {
                return ::testing::AssertionFailure()
                       << "2^" << k << " points, boxes 2^-" << a << " x 2^-" << k - a
                       << ": two points in box (" << cx << ", " << cy << ")";
            }
        }
    }
    return ::testing::AssertionSuccess();
}

// Whether the first 2^k values put exactly one in each [i / 2^k, (i + 1) / 2^k).
::testing::AssertionResult is_stratified_1d(const std::vector<float>& values, int k) {
    const std::size_t n = std::size_t{1} << k;
    std::vector<int> count(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const auto cell = static_cast<std::size_t>(values[i] * std::ldexp(1.0f, k));
        if (cell >= n || ++count[cell] > 1) {
            return ::testing::AssertionFailure() << "2^" << k << " values: two in cell " << cell;
        }
    }
    return ::testing::AssertionSuccess();
}

// Whether n = 2^k points in [0, 1)^D form a (t, k, D)-net in base 2: every elementary
// interval of volume 2^(t-k) (side 2^-a_j in dimension j, a_1 + ... + a_D = k - t) holds
// exactly 2^t points.
template <std::size_t D>
::testing::AssertionResult is_net(const std::vector<std::array<float, D>>& points, int k, int t) {
    const std::size_t n = std::size_t{1} << k;
    if (points.size() < n) return ::testing::AssertionFailure() << "too few points";
    if (t >= k) return ::testing::AssertionSuccess();
    std::array<int, D> a{};  // the current composition of k - t, enumerated in lexicographic order
    const auto next = [&]() {
        // The next composition of k - t into D parts; false after the last one.
        for (std::size_t j = D - 1; j > 0; --j) {
            int rest = 0;
            for (std::size_t i = j; i < D; ++i) rest += a[i];
            if (rest > 0) {
                ++a[j - 1];
                for (std::size_t i = j; i < D; ++i) a[i] = 0;
                a[D - 1] = rest - 1;
                return true;
            }
        }
        return false;
    };
    a[D - 1] = k - t;
    do {
        std::vector<int> count(std::size_t{1} << (k - t), 0);
        for (std::size_t i = 0; i < n; ++i) {
            std::size_t cell = 0;
            for (std::size_t j = 0; j < D; ++j) {
                const auto c = static_cast<std::size_t>(points[i][j] * std::ldexp(1.0f, a[j]));
                cell = (cell << a[j]) | c;  // exact: scaling by a power of 2
            }
            if (++count[cell] > (1 << t)) {
                return ::testing::AssertionFailure()
                       << "2^" << k << " points: more than 2^" << t << " in cell " << cell;
            }
        }
    } while (next());
    return ::testing::AssertionSuccess();
}

float to_unit(std::uint32_t bits) { return u32_to_unit_float(bits); }

// The draws of one camera path in the documented allocation: pixel and lens, then per
// bounce light choice, light, BSDF, roulette (start_bounce aligning each bounce).
struct PathDraws {
    std::vector<glm::vec2> pairs;
    std::vector<float> singles;
};

PathDraws draw_path(Sampler& sampler, int bounces) {
    PathDraws d;
    d.pairs.push_back(sampler.next_2d());
    d.pairs.push_back(sampler.next_2d());
    for (int b = 0; b < bounces; ++b) {
        sampler.start_bounce(static_cast<std::uint32_t>(b));
        d.singles.push_back(sampler.next_1d());
        d.pairs.push_back(sampler.next_2d());
        d.pairs.push_back(sampler.next_2d());
        d.singles.push_back(sampler.next_1d());
    }
    return d;
}

}  // namespace

TEST(Sobol, SecondDimensionIsThePascalMatrixModTwo) {
    // Joe and Kuo's dimension 2 (s = 1, a = 0, m = 1) generates the upper triangular Pascal
    // matrix mod 2: bit (31 - j) of direction number k is binomial(k, j) mod 2, which is
    // odd exactly when the bits of j are a subset of those of k (Lucas's theorem).
    for (std::uint32_t k = 0; k < 32; ++k) {
        std::uint32_t expected = 0;
        for (std::uint32_t j = 0; j <= k; ++j) {
            if ((j & k) == j) expected |= 1u << (31 - j);
        }
        EXPECT_EQ(sobol_u32(1u << k, 1), expected) << "k = " << k;
    }
}

TEST(Sobol, ByteTablesAgreeWithTheDirectionNumbers) {
    Pcg32 rng(5, 6);
    for (int i = 0; i < 20000; ++i) {
        const std::uint32_t index = i < 1000 ? static_cast<std::uint32_t>(i) : rng.next_u32();
        for (int d = 0; d < kSobolDimensions; ++d) {
            std::uint32_t x = 0;  // the defining sum: XOR of V_k over the set bits k of index
            for (int k = 0; k < 32; ++k) {
                if ((index >> k) & 1u) x ^= detail::kSobolMatrices[d][k];
            }
            ASSERT_EQ(sobol_u32(index, d), x) << "index " << index << " dim " << d;
            // The reversed tables give the same bits in reverse order.
            std::uint32_t reversed = 0;
            for (int k = 0; k < 32; ++k) reversed |= ((x >> k) & 1u) << (31 - k);
            ASSERT_EQ(sobol_reversed_u32(index, d), reversed) << "index " << index << " dim " << d;
            ASSERT_EQ(reverse_bits(x), reversed);
        }
    }
}

TEST(Sobol, PairTablesAndHalvesReversalAgreeWithTheDirectForm) {
    // sobol_reversed_pair(reverse(i)) = (reverse(sobol_u32(i, 0)), reverse(sobol_u32(i, 1)))
    // and reverse_bits_halves reverses each half and exchanges them: the forms the Sobol'
    // sampler's draws take, against the definitions.
    Pcg32 rng(7, 8);
    for (int n = 0; n < 20000; ++n) {
        const std::uint32_t i = n < 1000 ? static_cast<std::uint32_t>(n) : rng.next_u32();
        const std::uint64_t pair = sobol_reversed_pair(reverse_bits(i));
        ASSERT_EQ(static_cast<std::uint32_t>(pair), reverse_bits(sobol_u32(i, 0))) << i;
        ASSERT_EQ(static_cast<std::uint32_t>(pair >> 32u), reverse_bits(sobol_u32(i, 1))) << i;
        const std::uint32_t a = rng.next_u32(), b = rng.next_u32();
        const std::uint64_t v = reverse_bits_halves((std::uint64_t{a} << 32u) | b);
        ASSERT_EQ(static_cast<std::uint32_t>(v), reverse_bits(a));
        ASSERT_EQ(static_cast<std::uint32_t>(v >> 32u), reverse_bits(b));
    }
}

TEST(Sobol, EveryDimensionIsStratifiedAndTheFirstPairIsA02Sequence) {
    for (int d = 0; d < kSobolDimensions; ++d) {
        std::vector<float> values;
        for (std::uint32_t i = 0; i < 4096; ++i) values.push_back(to_unit(sobol_u32(i, d)));
        for (int k = 0; k <= 12; ++k) EXPECT_TRUE(is_stratified_1d(values, k)) << "dim " << d;
    }
    // A (0, 2)-sequence: the first 2^k points and every aligned block of 2^k are nets.
    for (const std::uint32_t block_start : {0u, 4096u, 1u << 20}) {
        std::vector<glm::vec2> points;
        for (std::uint32_t i = block_start; i < block_start + 4096; ++i) {
            points.emplace_back(to_unit(sobol_u32(i, 0)), to_unit(sobol_u32(i, 1)));
        }
        for (int k = 0; k <= 12; ++k) EXPECT_TRUE(is_02_net(points, k)) << block_start;
    }
}

TEST(Sobol, OwenScrambleIsABijectionThatKeepsNets) {
    // On 16-bit prefixes the scramble must permute the 2^16 elementary intervals.
    std::vector<int> seen(1u << 16, 0);
    for (std::uint32_t i = 0; i < (1u << 16); ++i) ++seen[owen_scramble(i << 16, 0x1234567u) >> 16];
    for (const int s : seen) ASSERT_EQ(s, 1);
    std::vector<glm::vec2> points;
    for (std::uint32_t i = 0; i < 1024; ++i) {
        points.emplace_back(to_unit(owen_scramble(sobol_u32(i, 0), 17u)),
                            to_unit(owen_scramble(sobol_u32(i, 1), 99u)));
    }
    for (int k = 0; k <= 10; ++k) EXPECT_TRUE(is_02_net(points, k));
}

TEST(SobolSampler, EveryPairAndSingleOfAPixelIsStratifiedForEveryPowerOfTwo) {
    constexpr int kMax = 10;
    constexpr int bounces = 3;
    for (const auto& [x, y, seed] :
         {std::tuple{0u, 0u, 0ull}, {17u, 3u, 42ull}, {511u, 400u, 7ull}}) {
        std::vector<PathDraws> samples;
        for (std::uint32_t s = 0; s < (1u << kMax); ++s) {
            Sampler sampler(SamplerKind::Sobol, x, y, s, seed);
            samples.push_back(draw_path(sampler, bounces));
        }
        for (std::size_t p = 0; p < samples[0].pairs.size(); ++p) {
            std::vector<glm::vec2> points;
            for (const PathDraws& d : samples) points.push_back(d.pairs[p]);
            for (int k = 0; k <= kMax; ++k) {
                if (p == 1) {
                    // The lens pair is Sobol' dimensions 2 and 3 (see the next test): a
                    // (t, 2)-sequence with t = (2 - 1) + (3 - 1) = 3, their polynomials'
                    // degrees less one (Sobol' 1967), not a (0, 2)-sequence.
                    std::vector<std::array<float, 2>> lens;
                    for (const glm::vec2& q : points) lens.push_back({q.x, q.y});
                    EXPECT_TRUE(is_net(lens, k, 3)) << "pixel " << x << "," << y << " lens";
                    continue;
                }
                EXPECT_TRUE(is_02_net(points, k)) << "pixel " << x << "," << y << " pair " << p;
            }
        }
        for (std::size_t q = 0; q < samples[0].singles.size(); ++q) {
            std::vector<float> values;
            for (const PathDraws& d : samples) values.push_back(d.singles[q]);
            for (int k = 0; k <= kMax; ++k) EXPECT_TRUE(is_stratified_1d(values, k)) << q;
        }
    }
}

TEST(SobolSampler, PixelAndLensAreOneFourDimensionalNet) {
    // The camera's four numbers are Sobol' dimensions 0..3 of one shuffled index, so every
    // 2^k samples of a pixel form a (3, k, 4)-net: t = 0 + 0 + 1 + 2, the degrees of the
    // four dimensions' polynomials less one (Sobol' 1967). Padding the lens pair with its
    // own shuffle (pairs stratified, their pairing random) fails this from k = 5 on.
    constexpr int kMax = 10;
    for (const auto& [x, y, seed] : {std::tuple{0u, 0u, 0ull}, {17u, 3u, 42ull}, {9u, 80u, 5ull}}) {
        std::vector<std::array<float, 4>> points;
        for (std::uint32_t s = 0; s < (1u << kMax); ++s) {
            Sampler sampler(SamplerKind::Sobol, x, y, s, seed);
            const glm::vec2 pixel = sampler.next_2d();
            const glm::vec2 lens = sampler.next_2d();
            points.push_back({pixel.x, pixel.y, lens.x, lens.y});
        }
        for (int k = 0; k <= kMax; ++k) {
            EXPECT_TRUE(is_net(points, k, 3)) << "pixel " << x << "," << y << " k = " << k;
        }
    }
}

TEST(SobolSampler, DependsOnPixelSampleAndSeedOnly) {
    const auto draws = [](std::uint32_t x, std::uint32_t y, std::uint32_t s, std::uint64_t seed) {
        Sampler sampler(SamplerKind::Sobol, x, y, s, seed);
        return draw_path(sampler, 4);
    };
    const PathDraws a = draws(5, 6, 7, 8);
    const PathDraws b = draws(5, 6, 7, 8);
    EXPECT_EQ(a.pairs, b.pairs);
    EXPECT_EQ(a.singles, b.singles);
    // Changing any one input changes the numbers.
    for (const PathDraws& other : {draws(6, 6, 7, 8), draws(5, 7, 7, 8), draws(5, 6, 8, 8),
                                   draws(5, 6, 7, 9), draws(6, 5, 7, 8)}) {
        EXPECT_NE(a.pairs, other.pairs);
    }
    // start_bounce makes a bounce's numbers independent of how many the previous drew.
    Sampler skipping(SamplerKind::Sobol, 5, 6, 7, 8);
    (void)skipping.next_2d();
    skipping.start_bounce(2);
    EXPECT_EQ(skipping.dimension(), SampleDimensions::bounce(2));
    EXPECT_EQ(skipping.next_1d(), a.singles[4]);
}

TEST(IndependentSampler, IsBitIdenticalToThePcgStreamOfThePixel) {
    for (const SamplerKind kind : {SamplerKind::Independent}) {
        Sampler legacy(3, 4, 5, 6);
        Sampler explicit_kind(kind, 3, 4, 5, 6);
        Pcg32 rng = make_sample_rng(3, 4, 5, 6);
        for (int i = 0; i < 50; ++i) {
            const float r = rng.next_float();
            const float a = legacy.next_1d();
            EXPECT_EQ(a, r);
            EXPECT_EQ(explicit_kind.next_1d(), r);
            if (i == 20) {
                // start_bounce does not touch the independent stream.
                legacy.start_bounce(3);
                explicit_kind.start_bounce(3);
            }
            const glm::vec2 expected = rng.next_vec2();
            EXPECT_EQ(legacy.next_2d(), expected);
            EXPECT_EQ(explicit_kind.next_2d(), expected);
        }
    }
}

namespace {

// A smooth integrand with a closed form: int_[0,1]^2 e^u sin(pi v) = (e - 1) 2 / pi.
double smooth(glm::vec2 u) { return std::exp(u.x) * std::sin(std::numbers::pi * u.y); }
constexpr double kSmoothIntegral = (std::numbers::e - 1.0) * 2.0 / std::numbers::pi;

// A discontinuous one, like an edge in a pixel: the quarter disk of radius^2 = 0.5.
double disk(glm::vec2 u) { return u.x * u.x + u.y * u.y < 0.5f ? 1.0 : 0.0; }
constexpr double kDiskIntegral = std::numbers::pi * 0.5 / 4.0;

// Direct lighting with a closed form: irradiance at the origin (normal +z) from a unit-
// radiance sphere of radius 1 at distance 3, 30 degrees off the normal, sampled by the
// cone it subtends (sample_sphere_direction). Wholly above the horizon, its projected
// solid angle is pi sin^2(alpha) cos(beta) with sin(alpha) = r / d (Nusselt analogue).
const glm::vec3 kLightCenter = 3.0f * glm::vec3(0.5f, 0.0f, 0.8660254f);
double direct_light(glm::vec2 u) {
    const SphereDirectionSample s = sample_sphere_direction(kLightCenter, 1.0f, glm::vec3(0.0f), u);
    return s.pdf > 0.0f ? std::max(0.0f, s.direction.z) / s.pdf : 0.0;
}
constexpr double kDirectLightIntegral = std::numbers::pi / 9.0 * 0.8660254037844386;

// Per-pixel errors of an n-sample estimate of f drawn from a high sampler dimension (the
// second bounce's BSDF pair), for `pixels` pixels along a row.
template <typename F>
std::vector<double> pixel_errors(SamplerKind kind, F f, double exact, int n, int pixels,
                                 std::uint64_t seed) {
    std::vector<double> errors;
    for (int p = 0; p < pixels; ++p) {
        double sum = 0.0;
        for (int s = 0; s < n; ++s) {
            Sampler sampler(kind, static_cast<std::uint32_t>(p % 64),
                            static_cast<std::uint32_t>(p / 64), static_cast<std::uint32_t>(s),
                            seed);
            sampler.set_dimension(SampleDimensions::bounce(1) + SampleDimensions::kBounceBsdf);
            sum += f(sampler.next_2d());
        }
        errors.push_back(sum / n - exact);
    }
    return errors;
}

struct ErrorStats {
    double mean = 0, variance = 0, neighbour_correlation = 0;
};

ErrorStats stats(const std::vector<double>& e) {
    ErrorStats s;
    const auto n = static_cast<double>(e.size());
    for (const double v : e) s.mean += v / n;
    double cov = 0.0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        s.variance += (e[i] - s.mean) * (e[i] - s.mean) / (n - 1);
        if (i + 1 < e.size()) cov += (e[i] - s.mean) * (e[i + 1] - s.mean) / (n - 1);
    }
    s.neighbour_correlation = cov / s.variance;
    return s;
}

}  // namespace

TEST(SobolSampler, PixelsAreUnbiasedUncorrelatedAndFarLessNoisyThanIndependent) {
    constexpr int pixels = 4096, n = 16;
    const ErrorStats sobol =
        stats(pixel_errors(SamplerKind::Sobol, smooth, kSmoothIntegral, n, pixels, 11));
    const ErrorStats indep =
        stats(pixel_errors(SamplerKind::Independent, smooth, kSmoothIntegral, n, pixels, 11));
    const double k = 4.0;  // standard errors allowed
    for (const ErrorStats& s : {sobol, indep}) {
        // Unbiased: the mean over pixels is within k standard errors of 0, which also needs
        // the pixels' errors to be independent (the mean then converges as 1/sqrt(pixels)).
        EXPECT_LT(std::abs(s.mean), k * std::sqrt(s.variance / pixels));
        // Neighbouring pixels' errors are uncorrelated: rho's standard error is 1/sqrt(n).
        EXPECT_LT(std::abs(s.neighbour_correlation), k / std::sqrt(double{pixels}));
    }
    // Owen-scrambled Sobol' on a smooth integrand: variance O(n^-3) against O(n^-1), so at
    // n = 16 far below the independent sampler's (the test asks for 20x; expected ~100x).
    EXPECT_LT(sobol.variance * 20.0, indep.variance)
        << "sobol " << sobol.variance << " independent " << indep.variance;
}

TEST(SobolSampler, ConvergenceFigure) {
    // RMSE over 1024 independent pixels against n = 1..1024 samples; the fitted log-log
    // slopes are the report's convergence figure.
    constexpr int pixels = 1024;
    struct Case {
        const char* name;
        double (*f)(glm::vec2);
        double exact;
        SamplerKind kind;
        double slope_lo, slope_hi;  // theory +- margin (slope noise is ~0.02 here)
    };
    const Case cases[] = {
        {"smooth independent", smooth, kSmoothIntegral, SamplerKind::Independent, -0.6, -0.4},
        {"smooth sobol", smooth, kSmoothIntegral, SamplerKind::Sobol, -1.7, -1.25},  // n^-1.5
        {"disk independent", disk, kDiskIntegral, SamplerKind::Independent, -0.6, -0.4},
        {"disk sobol", disk, kDiskIntegral, SamplerKind::Sobol, -0.95, -0.65},  // n^-0.75
        {"sphere light independent", direct_light, kDirectLightIntegral, SamplerKind::Independent,
         -0.6, -0.4},
        {"sphere light sobol", direct_light, kDirectLightIntegral, SamplerKind::Sobol, -1.7, -1.2},
    };
    for (const Case& c : cases) {
        std::vector<double> log_n, log_rmse;
        std::cout << c.name << ":";
        for (int n = 1; n <= 1024; n *= 4) {
            double mse = 0.0;
            for (const double e : pixel_errors(c.kind, c.f, c.exact, n, pixels, 3)) {
                mse += e * e / pixels;
            }
            log_n.push_back(std::log2(n));
            log_rmse.push_back(0.5 * std::log2(mse));
            std::cout << " n=" << n << " rmse=" << std::sqrt(mse);
        }
        // Least-squares slope of log rmse against log n.
        const auto m = static_cast<double>(log_n.size());
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        for (std::size_t i = 0; i < log_n.size(); ++i) {
            sx += log_n[i];
            sy += log_rmse[i];
            sxx += log_n[i] * log_n[i];
            sxy += log_n[i] * log_rmse[i];
        }
        const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
        std::cout << " slope=" << slope << "\n";
        RecordProperty(c.name, std::to_string(slope));
        EXPECT_GT(slope, c.slope_lo) << c.name;
        EXPECT_LT(slope, c.slope_hi) << c.name;
    }
}
