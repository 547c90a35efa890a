// The library's defaults are the documented best-measured settings (docs/using-librt.md,
// docs/render-your-own-scene.md "The defaults", the same as rt_render's, which
// apps/rt_render_test.sh checks): a RenderSettings{} renders Sobol' samples spread by
// adaptive sampling, and a PathTracerSettings{} ends paths by roulette from bounce 3 under
// a cap of 1000, not at the report's 5 bounces (so a closed white room converges to its
// value), choosing lights by bound above 16 of them.

#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

using namespace librt;

TEST(Defaults, RenderSettingsAreTheBestMeasured) {
    const RenderSettings s;
    EXPECT_EQ(s.sampler, SamplerKind::Sobol);
    EXPECT_TRUE(s.adaptive.enabled);
    EXPECT_EQ(s.adaptive.pilot_samples, 0);  // the largest power of two <= spp / 4
    EXPECT_EQ(s.adaptive.radius, 0);         // the image's larger side / 40, in [2, 16]
    EXPECT_EQ(s.adaptive.metric, AdaptiveMetric::Relative);  // the displayed image's error
    EXPECT_EQ(s.adaptive.relative_floor, 0.1);
    EXPECT_EQ(s.adaptive.max_factor, 8.0);
    EXPECT_EQ(s.block().sampler, SamplerKind::Sobol);  // what render_block is given
    EXPECT_EQ(BlockSettings{}.sampler, SamplerKind::Sobol);
    const ProgressiveSettings p;
    EXPECT_EQ(p.render.sampler, SamplerKind::Sobol);
    EXPECT_TRUE(p.render.adaptive.enabled);
    EXPECT_EQ(p.noise_target, 0.0);
    EXPECT_EQ(p.time_limit, 0.0);
}

TEST(Defaults, PathsEndByRouletteNotByALowCap) {
    const PathTracerSettings pt;
    EXPECT_EQ(pt.max_depth, 1000);
    EXPECT_TRUE(pt.russian_roulette);
    EXPECT_EQ(pt.russian_roulette_depth, 3);
    EXPECT_TRUE(pt.mis);
    EXPECT_EQ(pt.light_choice, LightChoice::Auto);
}

// Auto is Bounded above LightSampler::kMaxBounded lights (the light tree), Power up to it.
TEST(Defaults, AutoChoosesLightsByBoundAboveSixteen) {
    EXPECT_FALSE(chooses_by_bound(LightChoice::Auto, 1));
    EXPECT_FALSE(chooses_by_bound(LightChoice::Auto, LightSampler::kMaxBounded));
    EXPECT_TRUE(chooses_by_bound(LightChoice::Auto, LightSampler::kMaxBounded + 1));
    EXPECT_TRUE(chooses_by_bound(LightChoice::Bounded, 1));
    EXPECT_FALSE(chooses_by_bound(LightChoice::Power, 1000));
}
