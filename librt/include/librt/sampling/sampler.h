#pragma once

#include <librt/export.h>
#include <librt/sampling/rng.h>

#include <glm/vec2.hpp>

#include <cstdint>

namespace librt {

/// Where the random numbers of a camera path come from.
enum class SamplerKind : std::uint8_t {
    Independent,  ///< a PCG32 stream per (pixel, sample), as librt drew before Sobol' (the report
                  ///< apps')
    Sobol,        ///< Owen-scrambled Sobol' (camera: one 4D net; then padded 2D pairs)
};

/// The dimensions a camera path draws, in order. The camera takes the first four; each
/// bounce b then owns kPerBounce dimensions from kFirstBounce + b * kPerBounce, so a
/// decision draws from the same dimension in every sample of a pixel (and stays
/// stratified) even when an earlier bounce drew fewer numbers; Sampler::start_bounce
/// jumps there. Offsets inside a bounce are the kBounce* constants.
struct SampleDimensions {
    static constexpr std::uint32_t kPixel = 0;              ///< 2D: position in the pixel filter
    static constexpr std::uint32_t kLens = 2;               ///< 2D: point on the lens
    static constexpr std::uint32_t kFirstBounce = 4;        ///< first dimension of bounce 0
    static constexpr std::uint32_t kPerBounce = 7;          ///< dimensions each bounce owns
    static constexpr std::uint32_t kBounceLightChoice = 0;  ///< 1D: which light
    static constexpr std::uint32_t kBounceLight = 1;        ///< 2D: point on the light
    static constexpr std::uint32_t kBounceBsdf = 3;         ///< 2D: BSDF direction
    static constexpr std::uint32_t kBounceRoulette = 5;     ///< 1D: Russian roulette
    /// 1D: which BSDF lobe (materials with several); last, so the 2D direction keeps its
    /// dimension whether or not the material hit in this sample chooses a lobe.
    static constexpr std::uint32_t kBounceLobe = 6;
    /// 1D each: whether a path crosses a Null lobe (bsdf.h) or scatters there; the c-th
    /// crossing decision of a path takes kPassThrough + c. Far above every bounce's
    /// dimensions (bounce 1000 ends near 7000): a crossing is no bounce, and must not reuse
    /// a number a bounce draws.
    static constexpr std::uint32_t kPassThrough = 1u << 16u;

    /// First dimension of bounce `bounce` (0 = the camera ray's first hit).
    [[nodiscard]] static constexpr std::uint32_t bounce(std::uint32_t bounce) {
        return kFirstBounce + kPerBounce * bounce;
    }
};

/// The random numbers of one camera path. The renderer seeds it from (pixel, sample
/// index, seed), never from the thread, so images do not depend on how work is spread
/// over threads, tiles or processes.
///
/// One concrete class switching on its kind rather than a virtual interface: next_1d()
/// and next_2d() sit in the integrators' inner loops, and a branch the CPU predicts
/// perfectly (the kind never changes during a render) stays inlinable where a virtual
/// call through Integrator::li's `Sampler&` would not. The Independent path draws exactly
/// what librt always drew, so default renders are bit-identical to before.
///
/// Sobol: why padded, Owen-scrambled Sobol' and not pbrt-v4's ZSobol. ZSobol orders
/// samples along a Morton curve over pixels x samples, which needs the sample count
/// fixed and a power of two before rendering; a progressive film that adds samples, or a
/// distributed split by sample range, would change every pixel's points. Here each
/// pixel owns its own randomisation, so sample s of pixel p is the same whatever the
/// sample count, every prefix of 2^k samples is stratified, pixel errors are independent
/// (films merge and error estimates stay valid), and nothing depends on the resolution.
/// Every next_2d() takes Sobol' dimensions 0 and 1, the one pair of Sobol' dimensions that
/// is a (0, 2)-sequence, so each 2D decision is stratified as well as base 2 allows;
/// next_1d() takes dimension 0. Distinct sampler dimensions are decorrelated by Burley's
/// shuffle (an Owen scramble of the sample index, seeded per pixel and dimension) and by
/// independent Owen scrambles of the values. Joint stratification across pairs is given
/// up, the trade Burley 2020 discusses for padding; no dimension ever runs out. The one
/// exception is the camera: the lens pair shares the pixel pair's shuffle and takes
/// Sobol' dimensions 2 and 3, so pixel and lens form one 4D net (t = 3). Depth of field
/// makes what a camera ray hits depend on all four numbers at once (a blurred edge), and
/// there joint stratification measured 1.1-1.3x lower RMSE (docs/sampling.md); the lens
/// pair alone is then a (3, 2)-sequence rather than a (0, 2)-sequence.
class LIBRT_API Sampler {
public:
    /// An independent sampler drawing from a copy of an already seeded generator.
    explicit Sampler(const Pcg32& rng) : rng_(rng) {}
    /// Independent sampler for sample `sample_index` of pixel (x, y) in a render seeded
    /// with `seed`: the stream of make_sample_rng(x, y, sample_index, seed).
    Sampler(std::uint32_t x, std::uint32_t y, std::uint32_t sample_index, std::uint64_t seed)
        : rng_(make_sample_rng(x, y, sample_index, seed)) {}
    /// A sampler of the given kind for sample `sample_index` of pixel (x, y), seed `seed`.
    Sampler(SamplerKind kind, std::uint32_t x, std::uint32_t y, std::uint32_t sample_index,
            std::uint64_t seed)
        : kind_(kind) {
        if (kind == SamplerKind::Independent) {
            rng_ = make_sample_rng(x, y, sample_index, seed);
        } else {
            // A pixel key distinct from make_sample_rng's chain (another salt), so the two
            // kinds never share structure.
            pixel_key_ = mix64(mix64(seed ^ kSobolSalt) ^ ((std::uint64_t{x} << 32u) | y));
            reversed_index_ = reversed(sample_index);
        }
    }

    /// Uniform in [0, 1); takes one dimension.
    // Forced inline (both draws): g++ kept them out of line in the path loop, a call per
    // draw around a PCG32 step of a few instructions.
    [[nodiscard, gnu::always_inline]] float next_1d() {
        if (kind_ == SamplerKind::Independent) [[likely]] {
            return rng_.next_float();
        }
        return sobol_1d();
    }

    /// Uniform in [0, 1)^2; takes two dimensions.
    [[nodiscard, gnu::always_inline]] glm::vec2 next_2d() {
        if (kind_ == SamplerKind::Independent) [[likely]] {
            const float a = rng_.next_float();
            return {a, rng_.next_float()};
        }
        return sobol_2d();
    }

    /// Jumps to the dimensions of bounce `bounce` (see SampleDimensions). Sobol samplers
    /// draw from there on; the independent sampler's stream just continues (its numbers
    /// are independent anyway), so calling it never changes an independent render.
    void start_bounce(std::uint32_t bounce) { dimension_ = SampleDimensions::bounce(bounce); }

    /// Jumps to dimension `dimension` (the independent stream continues unchanged).
    void set_dimension(std::uint32_t dimension) { dimension_ = dimension; }

    /// The next dimension a Sobol sampler draws (an independent sampler only counts the
    /// jumps of start_bounce and set_dimension: its numbers have no dimensions).
    [[nodiscard]] std::uint32_t dimension() const { return dimension_; }

    /// Which kind of sampler this is.
    [[nodiscard]] SamplerKind kind() const { return kind_; }

private:
    // The Sobol' draws, out of line: inlined, their hashing would sit at every call site
    // of the integrators and slow the independent sampler (docs/benchmarks.md, "Code
    // shaped by measurement").
    [[nodiscard]] float sobol_1d();
    [[nodiscard]] glm::vec2 sobol_2d();
    /// reverse_bits(index) (sobol.h), out of line: sampler.h stays free of the tables.
    [[nodiscard]] static std::uint32_t reversed(std::uint32_t index);

    static constexpr std::uint64_t kSobolSalt = 0x5b0b01a5eedc0ffeULL;

    Pcg32 rng_;
    std::uint64_t pixel_key_ = 0;
    /// reverse_bits(sample index), computed once: every draw's Burley shuffle starts there.
    std::uint32_t reversed_index_ = 0;
    std::uint32_t dimension_ = 0;
    SamplerKind kind_ = SamplerKind::Independent;
};

}  // namespace librt
