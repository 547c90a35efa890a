#include <librt/core/error.h>
#include <librt/film/splat_film.h>
#include <librt/sampling/filter.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <thread>
#include <utility>
#include <vector>

using namespace librt;

namespace {

struct Splat {
    glm::vec2 raster;
    glm::vec3 value;
};

// Splats over the film and a little past its edges, values over eight decades (1e-4 to
// 1e4): sums of such values in float or double depend on the order.
std::vector<Splat> random_splats(int count, int width, int height, std::uint64_t seed) {
    Pcg32 rng(seed, 7);
    std::vector<Splat> out;
    out.reserve(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k) {
        const glm::vec2 u = rng.next_vec2();
        const glm::vec2 raster{-3.0f + u.x * (static_cast<float>(width) + 6.0f),
                               -3.0f + u.y * (static_cast<float>(height) + 6.0f)};
        const auto decade = [&] { return std::pow(10.0f, -4.0f + 8.0f * rng.next_float()); };
        out.push_back({raster, {decade(), decade(), decade()}});
    }
    return out;
}

// Adds splats[k] for k in `order` from `threads` threads, thread t taking every threads-th
// entry from t.
SplatFilm splat(const std::vector<Splat>& splats, const std::vector<std::size_t>& order,
                int threads, const FilterSettings& filter) {
    SplatFilm film(24, 16, filter);
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            for (std::size_t k = static_cast<std::size_t>(t); k < order.size();
                 k += static_cast<std::size_t>(threads)) {
                film.add(splats[order[k]].raster, splats[order[k]].value);
            }
        });
    }
    for (std::thread& thread : pool) thread.join();
    return film;
}

bool same_bytes(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// The total of all sums of a film that received one splat of value 1 (green channel), in
// the splat's units, and how many pixels it reached.
std::pair<double, int> total(const SplatFilm& film) {
    double sum = 0.0;
    int terms = 0;
    for (std::size_t p = 1; p < film.sums().size(); p += 3) {
        sum += std::ldexp(static_cast<double>(film.sums()[p]), -film.fraction_bits());
        if (film.sums()[p] != 0) ++terms;
    }
    return {sum, terms};
}

FilterSettings infinite_gaussian(float sigma) {
    FilterSettings g;
    g.kind = FilterKind::Gaussian;
    g.sigma = sigma;
    g.radius = std::numeric_limits<float>::infinity();
    return g;
}

}  // namespace

// The same multiset of splats, added in order, reversed, shuffled, and from 2 and 4
// threads, gives the same sums and byte-identical images; for the infinite Gaussian (36
// pixels a splat) and for Mitchell (negative lobes).
TEST(SplatFilm, AnyOrderAndThreadCountGiveIdenticalBytes) {
    const std::vector<Splat> splats = random_splats(60000, 24, 16, 3);
    std::vector<std::size_t> forward(splats.size());
    for (std::size_t k = 0; k < forward.size(); ++k) forward[k] = k;
    std::vector<std::size_t> backward(forward.rbegin(), forward.rend());
    std::vector<std::size_t> shuffled = forward;
    Pcg32 rng(11, 12);
    for (std::size_t k = shuffled.size() - 1; k > 0; --k) {  // Fisher-Yates
        std::swap(shuffled[k], shuffled[rng.next_u32() % (k + 1)]);
    }
    for (const FilterSettings& filter :
         {infinite_gaussian(0.5f), default_filter_settings(FilterKind::Mitchell)}) {
        const SplatFilm reference = splat(splats, forward, 1, filter);
        const Image image = reference.resolve(3.0);
        for (const auto& [order, threads] :
             {std::pair{&backward, 1}, {&shuffled, 1}, {&forward, 2}, {&shuffled, 4}}) {
            const SplatFilm film = splat(splats, *order, threads, filter);
            EXPECT_EQ(film.sums(), reference.sums()) << threads << " threads";
            EXPECT_TRUE(same_bytes(film.resolve(3.0), image)) << threads << " threads";
        }
        EXPECT_EQ(reference.clipped(), 0u);
        EXPECT_EQ(reference.non_finite(), 0u);
    }
}

// Two films holding halves of the splats merge into exactly the film of all of them.
TEST(SplatFilm, MergeIsExact) {
    const std::vector<Splat> splats = random_splats(20000, 24, 16, 4);
    const FilterSettings tent = default_filter_settings(FilterKind::Tent);
    SplatFilm all(24, 16, tent), first(24, 16, tent), second(24, 16, tent);
    for (std::size_t k = 0; k < splats.size(); ++k) {
        all.add(splats[k].raster, splats[k].value);
        (k % 3 == 0 ? first : second).add(splats[k].raster, splats[k].value);
    }
    second.merge(first);
    EXPECT_EQ(second.sums(), all.sums());
    EXPECT_TRUE(same_bytes(second.resolve(1.0), all.resolve(1.0)));
    SplatFilm other_size(24, 15, tent);
    EXPECT_THROW(other_size.merge(first), Error);
    SplatFilm other_filter(24, 16);
    EXPECT_THROW(other_filter.merge(first), Error);
}

// merge_sums (sums received from another process) adds as merge() does, counts included,
// and refuses sums of another size without changing the film.
TEST(SplatFilm, MergeSumsEqualsMerge) {
    const std::vector<Splat> splats = random_splats(5000, 12, 9, 8);
    SplatFilm all(12, 9), first(12, 9), second(12, 9);
    for (std::size_t k = 0; k < splats.size(); ++k) {
        all.add(splats[k].raster, splats[k].value);
        (k % 2 == 0 ? first : second).add(splats[k].raster, splats[k].value);
    }
    second.merge_sums(first.sums(), 3, 4);
    EXPECT_EQ(second.sums(), all.sums());
    EXPECT_EQ(second.clipped(), 3u);
    EXPECT_EQ(second.non_finite(), 4u);
    const std::vector<std::int64_t> before = second.sums();
    const std::vector<std::int64_t> short_sums(first.sums().begin(), first.sums().end() - 3);
    EXPECT_THROW(second.merge_sums(short_sums, 0, 0), Error);
    EXPECT_EQ(second.sums(), before);
}

// Box, tent and Mitchell (B + 2C = 1) weights are partitions of unity: one splat's weights
// sum to 1 wherever it lands, up to the rounding of each term to 2^-(k+1) and double
// rounding. The box gives all of it to the containing pixel [j, j + 1) x [i, i + 1).
TEST(SplatFilm, WeightsOfOneSplatSumToOne) {
    Pcg32 rng(61, 62);
    for (const FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Mitchell}) {
        for (int k = 0; k < 500; ++k) {
            SplatFilm film(16, 16, default_filter_settings(kind));
            // Away from the edges (radius <= 2), and on exact pixel edges now and then.
            glm::vec2 raster = glm::vec2(3.0f) + 10.0f * rng.next_vec2();
            if (k % 10 == 0) raster = {std::floor(raster.x), std::floor(raster.y)};
            film.add(raster, {0.0f, 1.0f, 0.0f});
            const auto [sum, terms] = total(film);
            const double rounding = terms * std::ldexp(0.5, -film.fraction_bits()) + 1e-12;
            EXPECT_NEAR(sum, 1.0, rounding) << static_cast<int>(kind) << " at " << raster.x;
            if (kind == FilterKind::Box) {
                EXPECT_EQ(terms, 1);
                const auto j = static_cast<std::size_t>(std::floor(raster.x));
                const auto i = static_cast<std::size_t>(std::floor(raster.y));
                EXPECT_EQ(film.sums()[3 * (i * 16 + j) + 1], std::int64_t{1} << 28);
            }
        }
    }
}

// A Gaussian's weights (sigma 0.5, infinite radius: the camera's PixelJitter::Gaussian,
// truncated at 5.03 sigma) sum to 1 up to its ripple: by Poisson summation one axis sums to
// 1 + 2 sum_k exp(-2 pi^2 sigma^2 k^2) cos(2 pi k x), within b = 2 sum_k exp(-2 pi^2
// sigma^2 k^2) = 0.01438 of 1, so a splat's weights within (1 + b)^2 - 1. Averaged over an
// 8 x 8 grid of positions in a pixel the harmonics below the 8th cancel, leaving the 8th
// (exp(-2 pi^2 sigma^2 64): nil), the truncation - it takes under 1e-6 of the mass from
// the weights and from the normalising integral alike, so at most 2e-6 - and the rounding.
TEST(SplatFilm, GaussianWeightsSumToOneUpToTheirRipple) {
    const FilterSettings filter = infinite_gaussian(0.5f);
    double ripple = 0.0;
    for (int k = 1; k < 10; ++k) {
        ripple += 2.0 * std::exp(-2.0 * std::numbers::pi * std::numbers::pi * 0.25 * k * k);
    }
    double mean = 0.0;
    int max_terms = 0;
    for (int a = 0; a < 8; ++a) {
        for (int b = 0; b < 8; ++b) {
            SplatFilm film(16, 16, filter);
            const glm::vec2 raster{8.0f + (static_cast<float>(a) + 0.3f) / 8.0f,
                                   7.0f + (static_cast<float>(b) + 0.6f) / 8.0f};
            film.add(raster, {0.0f, 1.0f, 0.0f});
            const auto [sum, terms] = total(film);
            EXPECT_NEAR(sum, 1.0, (1.0 + ripple) * (1.0 + ripple) - 1.0) << a << ", " << b;
            max_terms = std::max(max_terms, terms);
            mean += sum / 64.0;
        }
    }
    EXPECT_NEAR(mean, 1.0, 2.0 * SplatFilm::kTruncatedMass + max_terms * std::ldexp(0.5, -28));
}

// A splat's part beyond the bound is clipped and counted; the sum stays at the bound
// whatever comes after (sticky), so non-negative splats saturate the same in any order.
TEST(SplatFilm, SaturatesAtTheBoundsAndCountsIt) {
    // 62 fraction bits: the bound 2^63 - 1 units is 2.0 - 2^-62.
    SplatFilm film(4, 4, {}, 62);
    film.add({1.5f, 1.5f}, {1.5f, 0.0f, -1.5f});
    EXPECT_EQ(film.clipped(), 0u);
    film.add({1.5f, 1.5f}, {1.0f, 0.0f, -1.0f});  // 2.5 and -2.5: both past the bounds
    EXPECT_EQ(film.clipped(), 1u);
    const std::int64_t bound = std::numeric_limits<std::int64_t>::max();
    const std::size_t p = 3 * (1 * 4 + 1);
    EXPECT_EQ(film.sums()[p], bound);
    EXPECT_EQ(film.sums()[p + 2], -bound);
    film.add({1.5f, 1.5f}, {-1.0f, 0.0f, 1.0f});  // sticky: stays at the bounds
    EXPECT_EQ(film.sums()[p], bound);
    EXPECT_EQ(film.sums()[p + 2], -bound);
    EXPECT_EQ(film.clipped(), 2u);
    film.add({2.5f, 2.5f}, {1e30f, 0.0f, 0.0f});  // one term beyond int64
    EXPECT_EQ(film.clipped(), 3u);
    EXPECT_EQ(film.sums()[3 * (2 * 4 + 2)], bound);
    EXPECT_EQ(film.resolve(1.0).at(2, 2).x, 2.0f);

    // Non-negative splats that overflow together: the same bound in either order.
    SplatFilm a(1, 1, {}, 62), b(1, 1, {}, 62);
    for (const float v : {0.5f, 1.25f, 0.75f}) a.add({0.5f, 0.5f}, glm::vec3(v));
    for (const float v : {0.75f, 0.5f, 1.25f}) b.add({0.5f, 0.5f}, glm::vec3(v));
    EXPECT_EQ(a.sums(), b.sums());
    EXPECT_EQ(a.sums()[0], bound);
}

// NaN or infinite splats are counted and dropped; nothing of them is stored. Splats wholly
// off the film are dropped silently.
TEST(SplatFilm, DropsNonFiniteSplats) {
    SplatFilm film(8, 8, default_filter_settings(FilterKind::Tent));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    film.add({3.0f, 3.0f}, {nan, 1.0f, 1.0f});
    film.add({3.0f, 3.0f}, {1.0f, inf, 1.0f});
    film.add({nan, 3.0f}, {1.0f, 1.0f, 1.0f});
    film.add({3.0f, -inf}, {1.0f, 1.0f, 1.0f});
    film.add({-5.0f, 3.0f}, {1.0f, 1.0f, 1.0f});  // off the film
    EXPECT_EQ(film.non_finite(), 4u);
    EXPECT_EQ(film.clipped(), 0u);
    for (const std::int64_t s : film.sums()) EXPECT_EQ(s, 0);
}

// The margin a raster position can be off the image and still reach a pixel centre, and
// the constructor's checks.
TEST(SplatFilm, MarginAndValidation) {
    EXPECT_EQ(SplatFilm(4, 4).margin(), 0.0f);
    EXPECT_EQ(SplatFilm(4, 4, default_filter_settings(FilterKind::Tent)).margin(), 0.5f);
    EXPECT_NEAR(SplatFilm(4, 4, infinite_gaussian(0.5f)).radius(), 5.03 * 0.5, 1e-9);
    EXPECT_THROW(SplatFilm(-1, 4), Error);
    EXPECT_THROW(SplatFilm(4, 4, {}, 63), Error);
    FilterSettings wide;
    wide.radius = 40.0f;
    EXPECT_THROW(SplatFilm(4, 4, wide), Error);
    EXPECT_THROW((void)SplatFilm(4, 4).resolve(0.0), Error);
}
