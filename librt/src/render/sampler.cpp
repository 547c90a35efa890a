#include <librt/render/sampler.h>
#include <librt/sampling/sobol.h>

namespace librt {

namespace {

// Seeds of one dimension of a pixel: a splitmix64 chain, bijective in the dimension.
std::uint64_t dimension_hash(std::uint64_t pixel_key, std::uint32_t dimension) {
    return mix64(pixel_key + 0x9e3779b97f4a7c15ULL * (std::uint64_t{dimension} + 1));
}

std::uint32_t low_seed(std::uint64_t h) { return static_cast<std::uint32_t>(h); }

std::uint32_t high_seed(std::uint64_t h) { return static_cast<std::uint32_t>(h >> 32u); }

}  // namespace

float Sampler::sobol_1d() {
    const std::uint64_t h = dimension_hash(pixel_key_, dimension_++);
    // Burley's shuffle: this dimension's own permutation of the sample indices.
    const std::uint32_t index = owen_scramble(sample_index_, low_seed(h));
    return u32_to_unit_float(owen_scramble(sobol_u32(index, 0), high_seed(h)));
}

glm::vec2 Sampler::sobol_2d() {
    const std::uint64_t h = dimension_hash(pixel_key_, dimension_);
    dimension_ += 2;
    const std::uint32_t index = owen_scramble(sample_index_, low_seed(h));
    const std::uint64_t h2 = mix64(h);  // two more seeds for the two components
    return {u32_to_unit_float(owen_scramble(sobol_u32(index, 0), low_seed(h2))),
            u32_to_unit_float(owen_scramble(sobol_u32(index, 1), high_seed(h2)))};
}

}  // namespace librt
