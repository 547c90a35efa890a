// The cost of the samplers and pixel filters per camera path: a sampler built for
// (pixel, sample, seed) and the draws of a 3-bounce path in the documented allocation
// (pixel 2D, lens 2D, then per bounce light choice 1D, light 2D, BSDF 2D, roulette 1D).

#include <librt/sampling/filter.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>

#include <benchmark/benchmark.h>

#include <cstdint>

namespace {

// The Sampler as it was before SamplerKind (a bare Pcg32), to price the kind switch.
class LegacySampler {
public:
    LegacySampler(std::uint32_t x, std::uint32_t y, std::uint32_t s, std::uint64_t seed)
        : rng_(librt::make_sample_rng(x, y, s, seed)) {}
    float next_1d() { return rng_.next_float(); }
    glm::vec2 next_2d() {
        const float a = rng_.next_float();
        return {a, rng_.next_float()};
    }
    void start_bounce(std::uint32_t /*bounce*/) {}

private:
    librt::Pcg32 rng_;
};

template <typename MakeSampler>
void draw_paths(benchmark::State& state, MakeSampler make) {
    std::uint32_t sample = 0;
    for (auto _ : state) {
        auto sampler = make(sample & 255u, 17u, sample >> 8u);
        ++sample;
        glm::vec2 acc = sampler.next_2d() + sampler.next_2d();
        for (std::uint32_t bounce = 0; bounce < 3; ++bounce) {
            sampler.start_bounce(bounce);
            acc.x += sampler.next_1d();
            acc += sampler.next_2d() + sampler.next_2d();
            acc.y += sampler.next_1d();
        }
        benchmark::DoNotOptimize(acc);
    }
    state.counters["draws/s"] = benchmark::Counter(static_cast<double>(state.iterations()) * 18.0,
                                                   benchmark::Counter::kIsRate);
}

void BM_LegacySamplerPath(benchmark::State& state) {
    draw_paths(state, [](std::uint32_t x, std::uint32_t y, std::uint32_t s) {
        return LegacySampler(x, y, s, 1);
    });
}
BENCHMARK(BM_LegacySamplerPath);

// The new Sampler through the constructor the renderer calls today (independent).
void BM_DefaultSamplerPath(benchmark::State& state) {
    draw_paths(state, [](std::uint32_t x, std::uint32_t y, std::uint32_t s) {
        return librt::Sampler(x, y, s, 1);
    });
}
BENCHMARK(BM_DefaultSamplerPath);

void BM_SamplerPath(benchmark::State& state) {
    const auto kind = static_cast<librt::SamplerKind>(state.range(0));
    draw_paths(state, [kind](std::uint32_t x, std::uint32_t y, std::uint32_t s) {
        return librt::Sampler(kind, x, y, s, 1);
    });
}
BENCHMARK(BM_SamplerPath)
    ->Arg(static_cast<int>(librt::SamplerKind::Independent))
    ->Arg(static_cast<int>(librt::SamplerKind::Sobol))
    ->ArgName("kind(0=independent,1=sobol)");

void BM_PixelFilterSample(benchmark::State& state) {
    const librt::PixelFilter filter(
        librt::default_filter_settings(static_cast<librt::FilterKind>(state.range(0))));
    float u = 0.0f;
    for (auto _ : state) {
        u += 0.61803398875f;
        u -= static_cast<float>(static_cast<int>(u));
        benchmark::DoNotOptimize(filter.sample({u, 1.0f - u}));
    }
}
BENCHMARK(BM_PixelFilterSample)->DenseRange(0, 4)->ArgName("kind(box,tent,gauss,mitchell,bh)");

}  // namespace
