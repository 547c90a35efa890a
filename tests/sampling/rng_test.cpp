#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace librt;

namespace {

std::vector<std::uint32_t> draw(Pcg32 rng, int count) {
    std::vector<std::uint32_t> out(static_cast<std::size_t>(count));
    for (auto& v : out) v = rng.next_u32();
    return out;
}

// Pearson correlation of the first n floats of two generators.
double correlation(Pcg32 a, Pcg32 b, int n) {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (int i = 0; i < n; ++i) {
        const double x = a.next_float(), y = b.next_float();
        sa += x;
        sb += y;
        saa += x * x;
        sbb += y * y;
        sab += x * y;
    }
    const double nd = n;
    const double cov = sab / nd - (sa / nd) * (sb / nd);
    const double va = saa / nd - (sa / nd) * (sa / nd);
    const double vb = sbb / nd - (sb / nd) * (sb / nd);
    return cov / std::sqrt(va * vb);
}

}  // namespace

TEST(Pcg32, MatchesReferenceDemoOutput) {
    // pcg32_srandom_r(42, 54) in O'Neill's pcg32-demo prints these first six values.
    Pcg32 rng(42u, 54u);
    const std::array<std::uint32_t, 6> expected = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                                   0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    for (const std::uint32_t e : expected) EXPECT_EQ(rng.next_u32(), e);
}

TEST(Pcg32, AdvanceMatchesSteppingBothWays) {
    Pcg32 a(7u, 3u), b(7u, 3u);
    for (int i = 0; i < 1000; ++i) (void)a.next_u32();
    b.advance(1000);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a.next_u32(), b.next_u32());
    b.advance(-1001);
    EXPECT_EQ(b, Pcg32(7u, 3u));
    b.advance(0);
    EXPECT_EQ(b, Pcg32(7u, 3u));
}

TEST(Pcg32, UnitFloatNeverReachesOne) {
    EXPECT_EQ(u32_to_unit_float(0u), 0.0f);
    EXPECT_LT(u32_to_unit_float(0xffffffffu), 1.0f);
    EXPECT_EQ(u32_to_unit_float(0xffffffffu), 1.0f - 0x1p-24f);
    EXPECT_EQ(u32_to_unit_float(0x80000000u), 0.5f);

    Pcg32 rng(1u, 2u);
    constexpr int n = 1'000'000;
    for (int i = 0; i < n; ++i) {
        const float x = rng.next_float();
        ASSERT_GE(x, 0.0f);
        ASSERT_LT(x, 1.0f);
    }
}

TEST(Pcg32, MeanOfFloatsIsOneHalf) {
    Pcg32 rng = make_sample_rng(3, 5, 0, 2024);
    constexpr int n = 1'000'000;
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += rng.next_float();
    // U[0,1) has variance 1/12, so the mean of n draws has sigma sqrt(1/12/n).
    const double sigma = std::sqrt(1.0 / 12.0 / n);
    EXPECT_NEAR(sum / n, 0.5, 5.0 * sigma);
}

TEST(Pcg32, NextVec2DrawsXThenY) {
    Pcg32 a(9u, 9u), b(9u, 9u);
    const glm::vec2 v = a.next_vec2();
    EXPECT_EQ(v.x, b.next_float());
    EXPECT_EQ(v.y, b.next_float());
}

TEST(SampleRng, SameInputsGiveSameStream) {
    const auto a = draw(make_sample_rng(17, 42, 3, 99), 1000);
    const auto b = draw(make_sample_rng(17, 42, 3, 99), 1000);
    EXPECT_EQ(a, b);
}

TEST(SampleRng, EachInputChangesTheStream) {
    const auto base = draw(make_sample_rng(17, 42, 3, 99), 1000);
    const std::array<Pcg32, 7> others = {
        make_sample_rng(18, 42, 3, 99), make_sample_rng(17, 43, 3, 99),
        make_sample_rng(17, 42, 4, 99), make_sample_rng(17, 42, 3, 100),
        make_sample_rng(42, 17, 3, 99),  // swapped x and y
        make_sample_rng(0, 0, 0, 0),    make_sample_rng(0, 0, 0, 1)};
    for (const Pcg32& rng : others) {
        const auto other = draw(rng, 1000);
        // Two independent 32-bit streams agree at a position with probability 2^-32.
        int equal = 0;
        for (std::size_t i = 0; i < base.size(); ++i) equal += base[i] == other[i] ? 1 : 0;
        EXPECT_LE(equal, 1);
    }
}

TEST(SampleRng, NeighbouringPixelsAndSamplesAreUncorrelated) {
    // Correlation of independent streams has sigma ~ 1 / sqrt(n).
    constexpr int n = 20'000;
    const double tol = 5.0 / std::sqrt(static_cast<double>(n));
    const Pcg32 base = make_sample_rng(100, 100, 0, 7);
    EXPECT_NEAR(correlation(base, make_sample_rng(101, 100, 0, 7), n), 0.0, tol);
    EXPECT_NEAR(correlation(base, make_sample_rng(100, 101, 0, 7), n), 0.0, tol);
    EXPECT_NEAR(correlation(base, make_sample_rng(100, 100, 1, 7), n), 0.0, tol);
    EXPECT_NEAR(correlation(base, make_sample_rng(100, 100, 0, 8), n), 0.0, tol);
    // Lagged: pixel x+1 must not be pixel x shifted by a few draws.
    Pcg32 shifted = make_sample_rng(101, 100, 0, 7);
    for (int lag = 1; lag <= 3; ++lag) {
        (void)shifted.next_u32();
        EXPECT_NEAR(correlation(base, shifted, n), 0.0, tol);
    }
}
