// The path loop's frame-free evaluation of light samples (integrators.cpp's light_eval):
// a kind that provides eval_cos / pdf_cos must give what its eval / pdf give in the local
// frame, and ShadingFrame::facing must be ShadingFrame::at's second half.

#include "material/bsdf_diffuse.h"

#include <librt/material/bsdf.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/warp.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {
namespace {

glm::vec3 random_unit(Pcg32& rng) {
    return sample_uniform_sphere({rng.next_float(), rng.next_float()});
}

TEST(BsdfCosines, DiffuseCosineFormMatchesTheLocalFrame) {
    Pcg32 rng(7, 11);
    const Material m = Material::diffuse({0.7f, 0.5f, 0.3f});
    int compared = 0, reached = 0;
    for (int i = 0; i < 20000; ++i) {
        const glm::vec3 ng = random_unit(rng);
        // A shading normal bent off the geometric one (up to ~60 degrees), on its side.
        glm::vec3 ns = glm::normalize(ng + 0.9f * random_unit(rng));
        if (glm::dot(ns, ng) < 0.0f) ns = -ns;
        const glm::vec3 incoming = random_unit(rng);
        const glm::vec3 wi = random_unit(rng);

        const ShadingFrame at = ShadingFrame::at(ns, ng, incoming);
        const bool front = glm::dot(incoming, ng) < 0.0f;
        const glm::vec3 n = front ? ns : -ns, g = front ? ng : -ng;
        const ShadingFrame facing = ShadingFrame::facing(n, g, front);
        // Same inputs, same arithmetic: bit for bit the same frame.
        ASSERT_EQ(at.front, facing.front);
        ASSERT_EQ(at.shading.t, facing.shading.t);
        ASSERT_EQ(at.shading.b, facing.shading.b);
        ASSERT_EQ(at.shading.n, facing.shading.n);
        ASSERT_EQ(at.geometric, facing.geometric);

        const ShadingPoint p{at, m.albedo};
        const glm::vec3 wo = at.to_local(-incoming), wl = at.to_local(wi);
        const float cos_s = glm::dot(n, wi), cos_g = glm::dot(g, wi);
        // wi.z is exactly the world-space cosine with the facing shading normal.
        ASSERT_EQ(wl.z, cos_s);
        // The geometric side is tested in world space here and in the local frame by
        // eval(): only directions within rounding of the real surface may differ.
        if (std::fabs(cos_g) < 1e-5f) continue;
        ++compared;
        const glm::vec3 f = bsdfs::Diffuse::eval(m, p, wo, wl);
        const float pdf = bsdfs::Diffuse::pdf(m, p, wo, wl);
        EXPECT_EQ(bsdfs::Diffuse::eval_cos(p, cos_s, cos_g), f);
        EXPECT_EQ(bsdfs::Diffuse::pdf_cos(cos_s, cos_g), pdf);
        if (pdf > 0.0f) ++reached;
    }
    // Both branches (reached and not) were exercised many times.
    EXPECT_GT(compared, 19000);
    EXPECT_GT(reached, 2000);
    EXPECT_LT(reached, compared - 2000);
}

}  // namespace
}  // namespace librt
