#include <librt/sampling/rng.h>

namespace librt {

namespace {

constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;  // 2^64 / golden ratio

}  // namespace

void Pcg32::advance(std::int64_t delta) {
    // Jump ahead (Brown 1994): compose the affine map x -> a x + c with itself by
    // repeated squaring, accumulating the powers selected by the bits of delta.
    auto steps = static_cast<std::uint64_t>(delta);  // mod 2^64: negative goes back
    std::uint64_t cur_mult = kMultiplier, cur_plus = inc_;
    std::uint64_t acc_mult = 1, acc_plus = 0;
    while (steps > 0) {
        if (steps & 1u) {
            acc_mult *= cur_mult;
            acc_plus = acc_plus * cur_mult + cur_plus;
        }
        cur_plus = (cur_mult + 1) * cur_plus;  // c' = (a + 1) c: two steps of x -> a x + c
        cur_mult *= cur_mult;
        steps >>= 1u;
    }
    state_ = acc_mult * state_ + acc_plus;
}

Pcg32 make_sample_rng(std::uint32_t pixel_x, std::uint32_t pixel_y, std::uint32_t sample_index,
                      std::uint64_t seed) {
    // A hash chain of bijections: for a fixed seed the key is a bijection of the pixel,
    // and for a fixed pixel of the sample index, so distinct inputs collide only by
    // chance (~2^-64), never through structure.
    const std::uint64_t pixel = (std::uint64_t{pixel_x} << 32u) | pixel_y;
    std::uint64_t h = mix64(seed + kGolden);
    h = mix64(h ^ pixel);
    h = mix64(h ^ (std::uint64_t{sample_index} + kGolden));
    return Pcg32(h, mix64(h + kGolden));
}

}  // namespace librt
