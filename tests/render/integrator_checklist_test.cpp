// The brute-force tracer refusing the PathTracer settings it cannot honour.

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/geometry/ray_offset.h>
#include <librt/integrator/integrators.h>
#include <librt/material/bsdf.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>

namespace librt {
namespace {

// BruteForcePathTracer samples no light: the four PathTracer-only fields would change
// nothing, so it refuses them (naming field and value) instead of ignoring them.
TEST(IntegratorChecklist, BruteForceRefusesPathTracerOnlySettings) {
    const auto refusal = [](const PathTracerSettings& s) {
        try {
            BruteForcePathTracer brute(s);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    PathTracerSettings no_mis;
    no_mis.mis = false;
    PathTracerSettings bounded;
    bounded.light_choice = LightChoice::Bounded;
    PathTracerSettings guided;
    guided.guiding.enabled = true;
    PathTracerSettings caustics;
    caustics.caustic_paths.enabled = true;
    EXPECT_NE(refusal(no_mis).find("mis = false"), std::string::npos) << refusal(no_mis);
    EXPECT_NE(refusal(bounded).find("light_choice = Bounded"), std::string::npos);
    EXPECT_NE(refusal(guided).find("guiding.enabled = true"), std::string::npos);
    EXPECT_NE(refusal(caustics).find("caustic_paths.enabled = true"), std::string::npos);
    // The defaults, and the fields it reads, pass; PathTracer takes all four.
    EXPECT_EQ(refusal(PathTracerSettings{}), "");
    EXPECT_EQ(refusal(PathTracerSettings{7, false, 2}), "");
    for (const PathTracerSettings& s : {no_mis, bounded, guided, caustics})
        EXPECT_NO_THROW(PathTracer{s});
}

}  // namespace
}  // namespace librt
