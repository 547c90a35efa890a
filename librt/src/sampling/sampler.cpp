#include <librt/sampling/sampler.h>
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

// The draws below are owen_scramble(sobol_u32(owen_scramble(sample index, seed0), d), seed)
// (Burley 2020's shuffled, scrambled Sobol'), with the bit reversals that cancel removed:
// owen_scramble(v, s) = reverse(LK(reverse(v), s)) for Laine-Karras's LK, and
// reverse(sobol_u32(i, 0)) = i. The results are the same bits as the direct form (the
// Sobol' tests check it); callgrind counts the saving.

std::uint32_t Sampler::reversed(std::uint32_t index) { return reverse_bits(index); }

float Sampler::sobol_1d() {
    const std::uint64_t h = dimension_hash(pixel_key_, dimension_++);
    // Burley's shuffle: this dimension's own permutation of the sample indices, reversed
    // back to the index by the pair tables' low half (four loads, not a bit reversal).
    const std::uint32_t r = laine_karras_permutation(reversed_index_, low_seed(h));
    const auto index = static_cast<std::uint32_t>(sobol_reversed_pair(r));
    return u32_to_unit_float(reverse_bits(laine_karras_permutation(index, high_seed(h))));
}

glm::vec2 Sampler::sobol_2d() {
    const std::uint64_t h = dimension_hash(pixel_key_, dimension_);
    const std::uint64_t h2 = mix64(h);  // two more seeds for the two components
    if (dimension_ == SampleDimensions::kLens) {
        // The lens pair shares the pixel pair's shuffle and takes Sobol' dimensions 2 and
        // 3, so pixel and lens are one 4D Owen-scrambled net: jointly stratified where
        // depth of field makes the integrand depend on both (a blurred edge).
        dimension_ += 2;
        const std::uint64_t h0 = dimension_hash(pixel_key_, SampleDimensions::kPixel);
        const std::uint32_t index =
            reverse_bits(laine_karras_permutation(reversed_index_, low_seed(h0)));
        return {u32_to_unit_float(reverse_bits(
                    laine_karras_permutation(sobol_reversed_u32(index, 2), low_seed(h2)))),
                u32_to_unit_float(reverse_bits(
                    laine_karras_permutation(sobol_reversed_u32(index, 3), high_seed(h2))))};
    }
    dimension_ += 2;
    // The shuffled index stays reversed (r): the pair tables give both reversed Sobol'
    // values from it, and one reverse_bits_halves turns both scrambled values back.
    const std::uint32_t r = laine_karras_permutation(reversed_index_, low_seed(h));
    const std::uint64_t pair = sobol_reversed_pair(r);
    const std::uint32_t x =
        laine_karras_permutation(static_cast<std::uint32_t>(pair), low_seed(h2));
    const std::uint32_t y =
        laine_karras_permutation(static_cast<std::uint32_t>(pair >> 32u), high_seed(h2));
    const std::uint64_t v = reverse_bits_halves((std::uint64_t{x} << 32u) | y);
    return {u32_to_unit_float(static_cast<std::uint32_t>(v)),
            u32_to_unit_float(static_cast<std::uint32_t>(v >> 32u))};
}

}  // namespace librt
