#pragma once

#include <librt/export.h>

#include <glm/vec2.hpp>

#include <cstdint>

namespace librt {

/// The splitmix64 finaliser (Steele, Lea and Flood 2014): a bijection on 64 bits with full
/// avalanche, so keys differing in one bit give unrelated outputs. Used to hash seeds.
[[nodiscard]] constexpr std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30u)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27u)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31u);
}

/// Maps 32 random bits to a float in [0, 1): the top 24 bits times 2^-24, so every
/// value is exact and the largest is 1 - 2^-24 (never 1.0, which rounding would give).
[[nodiscard]] constexpr float u32_to_unit_float(std::uint32_t bits) {
    return static_cast<float>(bits >> 8) * 0x1p-24f;
}

/// PCG32 (O'Neill 2014): a 64-bit LCG state with the XSH-RR output permutation.
/// Small (16 bytes), fast, statistically strong, and each of its 2^63 streams
/// (selected by the odd increment) is an independent sequence of period 2^64.
/// Renderers should get one from make_sample_rng(), never share one across threads.
class LIBRT_API Pcg32 {
public:
    /// A fixed default stream, for tests and tools; renders use make_sample_rng().
    Pcg32() : Pcg32(0x853c49e6748fea9bULL, 0xda3e39cb94b95bdbULL) {}

    /// Seeds like the reference pcg32_srandom_r(): initstate = state_seed, initseq = stream.
    Pcg32(std::uint64_t state_seed, std::uint64_t stream) : inc_((stream << 1u) | 1u) {
        step();
        state_ += state_seed;
        step();
    }

    /// The next 32 uniformly distributed bits.
    [[nodiscard]] std::uint32_t next_u32() {
        const std::uint64_t old = state_;
        step();
        // XSH-RR: xorshift the high bits down, then rotate by the top 5 bits.
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }

    /// A uniform float in [0, 1); never 1.0.
    [[nodiscard]] float next_float() { return u32_to_unit_float(next_u32()); }

    /// Two uniform floats in [0, 1)^2, x drawn first.
    [[nodiscard]] glm::vec2 next_vec2() {
        const float x = next_float();
        const float y = next_float();
        return {x, y};
    }

    /// Skips delta outputs in O(log delta); a negative delta goes back (the period is 2^64).
    void advance(std::int64_t delta);

    /// True when both generators are at the same point of the same stream.
    [[nodiscard]] bool operator==(const Pcg32&) const = default;

private:
    static constexpr std::uint64_t kMultiplier = 6364136223846793005ULL;

    // One LCG step: state = state * a + c (mod 2^64).
    void step() { state_ = state_ * kMultiplier + inc_; }

    std::uint64_t state_ = 0;
    std::uint64_t inc_;  ///< always odd, so the LCG has full period
};

/// The generator for one (pixel, sample) of a render. (pixel_x, pixel_y, sample_index,
/// seed) are hashed through the splitmix64 finaliser into the PCG state and stream, so
/// a pixel's samples never depend on which thread draws them or in which order, and
/// neighbouring pixels or samples get unrelated streams rather than shifted copies.
[[nodiscard]] LIBRT_API Pcg32 make_sample_rng(std::uint32_t pixel_x, std::uint32_t pixel_y,
                                              std::uint32_t sample_index, std::uint64_t seed);

}  // namespace librt
