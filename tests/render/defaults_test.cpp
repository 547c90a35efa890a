// The library's defaults are the documented ones (docs/sampling.md): a RenderSettings{}
// draws independent numbers for every pixel alike (what librt always drew; rt_render's own
// defaults, Sobol' and adaptive sampling, are tested by apps/rt_render_test.sh), and a
// PathTracerSettings{} ends paths by roulette from bounce 3 under a cap of 1000, not at the
// report's 5 bounces, so a closed white room converges to its value.

#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

using namespace librt;

TEST(Defaults, RenderSettingsAreTheDocumentedOnes) {
    const RenderSettings s;
    EXPECT_EQ(s.sampler, SamplerKind::Independent);
    EXPECT_FALSE(s.adaptive.enabled);
    EXPECT_EQ(s.adaptive.radius, 8);
    EXPECT_EQ(s.adaptive.max_factor, 8.0);
    const ProgressiveSettings p;
    EXPECT_EQ(p.noise_target, 0.0);
    EXPECT_EQ(p.time_limit, 0.0);
}

TEST(Defaults, PathsEndByRouletteNotByALowCap) {
    const PathTracerSettings pt;
    EXPECT_EQ(pt.max_depth, 1000);
    EXPECT_EQ(pt.russian_roulette_depth, 3);
}
