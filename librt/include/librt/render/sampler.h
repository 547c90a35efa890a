#pragma once

#include <librt/sampling/rng.h>

#include <glm/vec2.hpp>

#include <cstdint>

namespace librt {

/// The random numbers of one camera path. The renderer seeds it from
/// (pixel, sample index, seed), never from the thread, so images do not depend on
/// how work is spread over threads.
class Sampler {
public:
    /// Sampler drawing from a copy of an already seeded generator.
    explicit Sampler(const Pcg32& rng) : rng_(rng) {}
    /// Sampler for sample `sample_index` of pixel (x, y) in a render seeded with `seed`.
    Sampler(std::uint32_t x, std::uint32_t y, std::uint32_t sample_index, std::uint64_t seed)
        : rng_(make_sample_rng(x, y, sample_index, seed)) {}

    /// Uniform in [0, 1).
    [[nodiscard]] float next_1d() { return rng_.next_float(); }
    /// Uniform in [0, 1)^2.
    [[nodiscard]] glm::vec2 next_2d() {
        const float a = rng_.next_float();
        return {a, rng_.next_float()};
    }

private:
    Pcg32 rng_;
};

}  // namespace librt
