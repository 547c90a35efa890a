// The BSDF seam: for every material kind, sample() agrees with eval() and pdf() (the
// returned weight is f cos / pdf at the sampled direction, the returned pdf is pdf()'s),
// lobe flags say what the kind does, and the sampled directions of the non-delta kinds
// follow pdf() (chi-square), including where a bent shading normal makes sample() fail.

#include "sampling/chi_square.h"
#include "sampling/direction_bins.h"

#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace librt {
namespace {

using testing::chi_square_test;
using testing::DirectionBins;

/// A unit vector from two uniform numbers (uniform on the sphere).
glm::vec3 random_direction(Pcg32& rng) { return sample_uniform_sphere(rng.next_vec2()); }

/// A shading point with shading normal ns, geometric normal ng (ns turned onto ng's side
/// like Scene does) and a ray arriving along `incoming`.
ShadingPoint point_at(glm::vec3 ns, const glm::vec3& ng, const glm::vec3& incoming,
                      const glm::vec3& albedo) {
    if (glm::dot(ns, ng) < 0.0f) ns = -ns;
    return {ShadingFrame::at(ns, ng, incoming), albedo};
}

/// n times the integral of pdf over each cell of bins (d omega = d cos d phi), by the
/// midpoint rule on 16 x 16 sub-cells: fine enough that a cell cut by a boundary where
/// pdf falls continuously to 0 is not estimated as empty while samples land in it.
std::vector<double> fine_expected_counts(const DirectionBins& bins,
                                         const std::function<double(const glm::vec3&)>& pdf,
                                         int n) {
    constexpr int sub = 16;
    const double dc = (bins.cos_hi - bins.cos_lo) / (bins.n_cos * sub);
    const double dphi = testing::kTwoPi / (bins.n_phi * sub);
    std::vector<double> expected(std::size_t(bins.size()), 0.0);
    for (int i = 0; i < bins.n_cos * sub; ++i)
        for (int j = 0; j < bins.n_phi * sub; ++j) {
            const double c = bins.cos_lo + (i + 0.5) * dc, phi = (j + 0.5) * dphi;
            expected[std::size_t((i / sub) * bins.n_phi + j / sub)] +=
                n * pdf(bins.direction(c, phi)) * dc * dphi;
        }
    return expected;
}

struct Kind {
    std::string name;
    Material material;
};

std::vector<Kind> all_kinds() {
    return {{"diffuse", Material::diffuse({0.2f, 0.5f, 0.9f})},
            {"mirror", Material::mirror({0.9f, 0.8f, 0.7f})},
            {"glass (Fresnel)", Material::dielectric(1.5f, true, {1.0f, 0.9f, 0.8f})},
            {"glass (no Fresnel)", Material::dielectric(1.4f, false)},
            {"emissive", Material::emissive(glm::vec3(3.0f))}};
}

TEST(Bsdf, LobesSayWhatEachKindDoes) {
    EXPECT_EQ(lobes(Material::diffuse(glm::vec3(0.5f))), BsdfLobe::DiffuseReflection);
    EXPECT_EQ(lobes(Material::mirror()), BsdfLobe::SpecularReflection);
    EXPECT_EQ(lobes(Material::dielectric(1.5f)),
              BsdfLobe::SpecularReflection | BsdfLobe::SpecularTransmission);
    EXPECT_EQ(lobes(Material::emissive(glm::vec3(1.0f))), BsdfLobe::None);
    EXPECT_TRUE(has_non_specular(lobes(Material::diffuse(glm::vec3(0.5f)))));
    EXPECT_FALSE(has_non_specular(lobes(Material::dielectric(1.5f))));
    for (const Kind& k : all_kinds())
        EXPECT_EQ(k.material.is_specular(),
                  lobes(k.material) != BsdfLobe::None && !has_non_specular(lobes(k.material)))
            << k.name;
}

// For random frames (shading normal bent up to ~60 degrees off the geometric one), random
// incoming rays from both sides and random (uc, u): a valid sample's lobe is one of the
// material's, its direction is unit, and
// - for a non-specular lobe, pdf equals pdf(wo, wi) and weight equals
//   eval(wo, wi) |cos| / pdf, and the direction is above the real surface;
// - for a specular lobe, eval and pdf are 0 there (no density), and pdf is a probability.
TEST(Bsdf, SampleAgreesWithEvalAndPdf) {
    Pcg32 rng(17, 3);
    for (const Kind& k : all_kinds()) {
        int valid = 0;
        for (int i = 0; i < 20000; ++i) {
            const glm::vec3 ng = random_direction(rng);
            const glm::vec3 ns = glm::normalize(ng + 0.9f * random_direction(rng));
            const glm::vec3 incoming = random_direction(rng);
            const ShadingPoint sp = point_at(ns, ng, incoming, k.material.albedo);
            const glm::vec3 wo = sp.frame.to_local(-incoming);
            const BsdfSample s = sample(k.material, sp, wo, rng.next_float(), rng.next_vec2());
            if (!s.valid()) continue;
            ++valid;
            ASSERT_TRUE(has(lobes(k.material), s.lobe)) << k.name;
            ASSERT_NEAR(glm::length(s.wi), 1.0f, 1e-5f) << k.name;
            const glm::vec3 f = eval(k.material, sp, wo, s.wi);
            const float p = pdf(k.material, sp, wo, s.wi);
            if (has(s.lobe, BsdfLobe::Specular)) {
                EXPECT_EQ(f, glm::vec3(0.0f)) << k.name;
                EXPECT_EQ(p, 0.0f) << k.name;
                ASSERT_GT(s.pdf, 0.0f) << k.name;
                ASSERT_LE(s.pdf, 1.0f) << k.name;
                // Both lobes of glass and the mirror carry the tint: F / P(F) = 1.
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(s.weight[c], k.material.albedo[c], 1e-6f);
                // Reflection stays on wo's side of the real surface, transmission crosses it.
                EXPECT_EQ(sp.frame.above_geometry(s.wi), has(s.lobe, BsdfLobe::Reflection))
                    << k.name;
            } else {
                ASSERT_NEAR(s.pdf, p, 1e-5f * p) << k.name;
                ASSERT_TRUE(sp.frame.above_geometry(s.wi)) << k.name;
                const glm::vec3 expected = f * std::fabs(s.wi.z) / p;
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(s.weight[c], expected[c], 1e-5f * expected[c] + 1e-7f)
                        << k.name << " channel " << c;
            }
        }
        if (lobes(k.material) == BsdfLobe::None) {
            EXPECT_EQ(valid, 0) << k.name << " scatters nothing";
        } else {
            EXPECT_GT(valid, 15000) << k.name;
        }
    }
}

// Diffuse: f = albedo / pi above the surface, 0 below either normal; pdf = cos / pi.
TEST(Bsdf, DiffuseEvalIsLambert) {
    const Material m = Material::diffuse({0.2f, 0.5f, 0.9f});
    const glm::vec3 n(0, 0, 1);
    const ShadingPoint sp = point_at(n, n, {0.3f, 0.1f, -1.0f}, m.albedo);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.1f, 0.2f, 1.0f));
    const glm::vec3 wi = glm::normalize(glm::vec3(-0.5f, 0.3f, 0.6f));
    const glm::vec3 f = eval(m, sp, wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], m.albedo[c] / kPi, 1e-7f);
    EXPECT_NEAR(pdf(m, sp, wo, wi), wi.z / kPi, 1e-7f);
    EXPECT_EQ(eval(m, sp, wo, -wi), glm::vec3(0.0f));
    EXPECT_EQ(pdf(m, sp, wo, -wi), 0.0f);
    // From the back of the surface the frame turns over: still Lambert on that side.
    const ShadingPoint back = point_at(n, n, {0.3f, 0.1f, 1.0f}, m.albedo);
    EXPECT_NEAR(eval(m, back, wo, wi).x, m.albedo.x / kPi, 1e-7f);
    EXPECT_FALSE(back.frame.front);
    EXPECT_TRUE(sp.frame.front);
}

// Chi-square of diffuse sampling against pdf() over the whole sphere of local directions,
// plus one cell for failed samples, which must hold 1 - (integral of pdf): with matching
// normals none fail; with the shading normal bent 50 degrees off the geometric one, the
// cosine lobe reaches under the real surface and those samples fail.
TEST(Bsdf, DiffuseDirectionsFollowPdf) {
    const Material m = Material::diffuse(glm::vec3(0.7f));
    const glm::vec3 ng(0, 0, 1);
    for (const float bend : {0.0f, 0.87f}) {
        const glm::vec3 ns(std::sin(bend), 0.0f, std::cos(bend));
        const ShadingPoint sp = point_at(ns, ng, glm::normalize(glm::vec3(-1, 0.5f, -1)), m.albedo);
        const glm::vec3 wo = sp.frame.to_local(glm::normalize(glm::vec3(1, -0.5f, 1)));
        // Cells around the geometric normal, so that the jump of pdf() to 0 under the real
        // surface lies on cell edges; at the shading normal's horizon pdf() falls to 0
        // continuously (as cos), so cells cut there are integrated well by fine quadrature.
        DirectionBins bins;
        bins.frame = Frame::from_normal(sp.frame.geometric);
        bins.n_cos = 20;
        bins.n_phi = 40;
        const int n = 200'000;
        std::vector<double> observed(std::size_t(bins.size()) + 1, 0.0);
        Pcg32 rng(5, 7);
        for (int i = 0; i < n; ++i) {
            const BsdfSample s = sample(m, sp, wo, rng.next_float(), rng.next_vec2());
            const int cell = s.valid() ? bins.cell(s.wi) : bins.size();
            ASSERT_GE(cell, 0);
            observed[std::size_t(cell)] += 1.0;
        }
        std::vector<double> expected = fine_expected_counts(
            bins, [&](const glm::vec3& w) { return double(pdf(m, sp, wo, w)); }, n);
        double total = 0.0;
        for (const double e : expected) total += e;
        expected.push_back(std::max(0.0, n - total));
        if (bend == 0.0f) {
            EXPECT_EQ(observed.back(), 0.0) << "no sample fails with matching normals";
            EXPECT_NEAR(total / n, 1.0, 2e-3);
        } else {
            EXPECT_GT(observed.back(), 0.01 * n) << "the bent lobe reaches under the surface";
        }
        const testing::ChiSquareResult r = chi_square_test(observed, expected);
        EXPECT_TRUE(r.error.empty()) << r.summary();
        EXPECT_GE(r.p_value, 0.01) << "bend " << bend << ": " << r.summary();
    }
}

// The mirror reflects about the shading normal, or about the geometric one when that
// would go under the real surface.
TEST(Bsdf, MirrorReflectsAboutTheShadingNormal) {
    const Material m = Material::mirror(glm::vec3(0.5f));
    const glm::vec3 n(0, 1, 0);
    const glm::vec3 d = glm::normalize(glm::vec3(1, -1, 0));
    const ShadingPoint sp = point_at(n, n, d, m.albedo);
    const BsdfSample s = sample(m, sp, sp.frame.to_local(-d), 0.5f, glm::vec2(0.5f));
    ASSERT_TRUE(s.valid());
    EXPECT_EQ(s.lobe, BsdfLobe::SpecularReflection);
    EXPECT_NEAR(glm::length(sp.frame.to_world(s.wi) - glm::normalize(glm::vec3(1, 1, 0))), 0.0f,
                1e-6f);
    // A shading normal tilted so far that its reflection of a grazing ray goes under.
    const glm::vec3 ns = glm::normalize(glm::vec3(-1.0f, 0.3f, 0.0f));
    const glm::vec3 grazing = glm::normalize(glm::vec3(1.0f, -0.05f, 0.0f));
    const ShadingPoint bent = point_at(ns, n, grazing, m.albedo);
    const BsdfSample g = sample(m, bent, bent.frame.to_local(-grazing), 0.5f, glm::vec2(0.5f));
    ASSERT_TRUE(g.valid());
    EXPECT_GT(glm::dot(bent.frame.to_world(g.wi), n), 0.0f);
}

}  // namespace
}  // namespace librt
