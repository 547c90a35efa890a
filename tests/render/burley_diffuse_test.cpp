// Burley's diffuse (DiffuseModel::Burley, Burley 2012 "Physically Based Shading at Disney",
// sec. 5.3) as the metallic-roughness material's base, against mathematics: with the
// specular layer off (specularFactor 0) eval() is the closed form c / pi (1 + (F_D90 - 1)
// (1 - cos_i)^5)(1 + (F_D90 - 1)(1 - cos_o)^5), F_D90 = 0.5 + 2 r (wi.h)^2, written here in
// double; sample() agrees with eval() and pdf(); reciprocity; chi-square of sampled
// directions against pdf(); its directional albedo (the white furnace of one bounce)
// equals the test's own quadrature of the closed form, and stays under the bound the
// formula gives: each factor lies between 1 and F_D90 <= 0.5 + 2 r, so the albedo is at
// most 1 for r <= 0.25 and at most (0.5 + 2 r)^2 above. Lambert stays the default.

#include "render/bsdf_chi_square_util.h"
#include "render/microfacet_test_util.h"
#include "sampling/chi_square.h"
#include "sampling/direction_bins.h"
#include "sampling/sanitizer_scale.h"

#include <librt/core/error.h>
#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace librt {
namespace {

using testing::Case;
using testing::flat_point;
using testing::local_dir;

Material burley(const glm::vec3& c, float metallic, float roughness, float transmission = 0.0f) {
    Material m = Material::metallic_roughness(c, metallic, roughness, 1.5f, transmission);
    m.diffuse_model = DiffuseModel::Burley;
    return m;
}

/// Burley's diffuse for base colour 1 in double, from the paper's formula.
double ref_burley(const glm::dvec3& wo, const glm::dvec3& wi, double r) {
    const glm::dvec3 h = glm::normalize(wo + wi);
    const double cd = glm::dot(wi, h);
    const double fd90 = 0.5 + 2.0 * r * cd * cd;
    const auto fd = [&](double c) { return 1.0 + (fd90 - 1.0) * std::pow(1.0 - c, 5.0); };
    return fd(wi.z) * fd(wo.z) / std::numbers::pi;
}

/// Its directional albedo at cos_o by midpoint quadrature over (cos_i, phi).
double ref_burley_albedo(double co, double r) {
    const glm::dvec3 wo(std::sqrt(1.0 - co * co), 0.0, co);
    const int nc = 400, np = 200;
    double sum = 0.0;
    for (int i = 0; i < nc; ++i) {
        const double ci = (i + 0.5) / nc, si = std::sqrt(1.0 - ci * ci);
        for (int j = 0; j < np; ++j) {
            const double phi = 2.0 * std::numbers::pi * (j + 0.5) / np;
            const glm::dvec3 wi(si * std::cos(phi), si * std::sin(phi), ci);
            sum += ref_burley(wo, wi, r) * ci;
        }
    }
    return sum * 2.0 * std::numbers::pi / (nc * np);
}

/// Burley bases: plain, with metal and transmission, with layers, anisotropic.
std::vector<Case> burley_cases(float r) {
    const std::string s = " r=" + std::to_string(r);
    Material layered = burley({0.9f, 0.8f, 0.7f}, 0.0f, r);
    layered.clearcoat = 0.5f;
    layered.clearcoat_roughness = 0.6f;
    layered.sheen_color = {0.4f, 0.4f, 0.4f};
    layered.sheen_roughness = 0.7f;
    Material aniso = burley({0.3f, 0.6f, 0.9f}, 0.2f, r);
    aniso.anisotropy = 0.6f;
    return {{"plain" + s, burley({0.8f, 0.5f, 0.2f}, 0.0f, r)},
            {"metal+transmission" + s, burley({0.9f, 0.9f, 0.6f}, 0.3f, r, 0.4f)},
            {"layered" + s, layered},
            {"anisotropic" + s, aniso}};
}

constexpr float kRoughness[] = {0.05f, 0.3f, 0.8f};

TEST(BurleyDiffuse, LambertIsTheDefault) {
    EXPECT_EQ(Material{}.diffuse_model, DiffuseModel::Lambert);
    EXPECT_EQ(Material::metallic_roughness(glm::vec3(0.5f), 0.0f, 0.5f).diffuse_model,
              DiffuseModel::Lambert);
    Material bad = burley(glm::vec3(0.5f), 0.0f, 0.5f);
    bad.diffuse_model = DiffuseModel(7);
    EXPECT_THROW(validate(bad), Error);
}

// Specular layer off: eval() is exactly the closed form (a coloured base scales it), and
// the same material with Lambert is c / pi.
TEST(BurleyDiffuse, EvalIsTheClosedForm) {
    Pcg32 rng(3, 8);
    const glm::vec3 c(0.9f, 0.5f, 0.25f);
    for (const float r : {0.0f, 0.25f, 0.6f, 1.0f}) {
        Material m = burley(c, 0.0f, r);
        m.specular = 0.0f;
        Material lambert = m;
        lambert.diffuse_model = DiffuseModel::Lambert;
        const ShadingPoint p = flat_point();
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 wo =
                local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
            const glm::vec3 wi =
                local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
            const double expected = ref_burley(glm::dvec3(wo), glm::dvec3(wi), r);
            const glm::vec3 f = eval(m, p, wo, wi);
            const glm::vec3 fl = eval(lambert, p, wo, wi);
            for (int k = 0; k < 3; ++k) {
                ASSERT_NEAR(f[k], c[k] * expected, 2e-5 * c[k] * expected + 1e-7)
                    << "r " << r << " i " << i;
                ASSERT_NEAR(fl[k], c[k] / std::numbers::pi, 1e-6) << "r " << r;
            }
        }
    }
}

TEST(BurleyDiffuse, SampleWeightIsEvalCosOverPdf) {
    Pcg32 rng(5, 21);
    for (const float r : kRoughness)
        for (const Case& c : burley_cases(r)) {
            const ShadingPoint p = flat_point(c.front);
            int valid = 0;
            for (int i = 0; i < 20000; ++i) {
                const glm::vec3 wo =
                    local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
                const BsdfSample s = sample(c.material, p, wo, rng.next_float(), rng.next_vec2());
                if (!s.valid()) continue;
                ++valid;
                ASSERT_TRUE(testing::sample_agrees_with_eval_pdf(c.material, p, wo, s)) << c.name;
            }
            EXPECT_GT(valid, 10000) << c.name;
        }
}

TEST(BurleyDiffuse, IsReciprocalAndNonNegative) {
    Pcg32 rng(9, 4);
    for (const float r : kRoughness)
        for (const Case& c : burley_cases(r)) {
            const ShadingPoint p = flat_point(c.front);
            for (int i = 0; i < 5000; ++i) {
                const glm::vec3 a = local_dir(rng.next_float(), 6.283 * rng.next_float());
                const glm::vec3 b = local_dir(rng.next_float(), 6.283 * rng.next_float());
                const glm::vec3 fab = eval(c.material, p, a, b), fba = eval(c.material, p, b, a);
                for (int k = 0; k < 3; ++k) {
                    ASSERT_GE(fab[k], 0.0f) << c.name;
                    ASSERT_TRUE(std::isfinite(fab[k])) << c.name;
                    ASSERT_NEAR(fab[k], fba[k], 1e-4f * fab[k] + 1e-7f) << c.name;
                }
            }
        }
}

// Chi-square over equal-solid-angle cells of the sphere, expected counts by quadrature of
// pdf() (as GltfLayers.SampledDirectionsFollowPdf), plus a cell for failed samples.
// Roughness 0.3 only down to cos_o 0.5: at 0.2 the plain and metal+transmission cases fail
// (p 1e-6, 1e-9) with the very same chi^2 when their diffuse is Lambert's (measured: the
// diffuse model changes eval() only, not sample() or pdf()), so that is the existing
// lobe's (or this quadrature's, of a GGX lobe of alpha 0.09 at 78 degrees), not Burley's.
TEST(BurleyDiffuse, SampledDirectionsFollowPdf) {
    const int n = testing::scaled_samples(100'000);
    for (const float r : {0.3f, 0.8f})
        for (const Case& c : burley_cases(r))
            for (const double co : {0.9, 0.5, 0.2}) {
                if (r < 0.5f && co < 0.5) continue;
                const ShadingPoint p = flat_point(c.front);
                const glm::vec3 wo = local_dir(co, 0.3);
                Pcg32 rng(uint64_t(1000 * r + 10 * co), 11);
                testing::expect_sampling_follows_pdf(c.material, p, wo, n, rng,
                                                     c.name + " cos_o " + std::to_string(co));
            }
}

// The white furnace of one bounce: a white Burley base without the specular layer
// reflects, at each cos_o, the quadrature of the closed form (within 4 standard errors of
// the sampled mean, plus 1e-3 for the quadrature), and that albedo is under the formula's
// bound: 1 for r <= 0.25 (F_D90 <= 1: both factors <= 1, energy conserving), (0.5 + 2 r)^2
// above (not energy conserving: a rough white surface seen at grazing angles returns more
// than 1, as in Cycles; the test asserts the bound, and that it exceeds 1 somewhere).
TEST(BurleyDiffuse, WhiteFurnaceMatchesQuadratureUnderItsBound) {
    const int n = testing::scaled_samples(100'000);
    bool above_one = false;
    for (const float r : {0.0f, 0.25f, 0.5f, 1.0f})
        for (const double co : {1.0, 0.7, 0.3, 0.05}) {
            Material m = burley(glm::vec3(1.0f), 0.0f, r);
            m.specular = 0.0f;
            const double expected = ref_burley_albedo(co, r);
            const double bound = r <= 0.25f ? 1.0 : (0.5 + 2.0 * r) * (0.5 + 2.0 * r);
            EXPECT_LE(expected, bound) << "r " << r << " cos_o " << co;
            above_one = above_one || expected > 1.0;
            const ShadingPoint p = flat_point();
            const glm::vec3 wo = local_dir(co, 0.4);
            Pcg32 rng(17, uint64_t(100 * r + 10 * co));
            double sum = 0.0, sum2 = 0.0;
            for (int i = 0; i < n; ++i) {
                const BsdfSample s = sample(m, p, wo, rng.next_float(), rng.next_vec2());
                const double w = s.valid() ? double(s.weight.x) : 0.0;
                sum += w;
                sum2 += w * w;
            }
            const double mean = sum / n;
            const double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
            EXPECT_NEAR(mean, expected, 4.0 * se + 1e-3) << "r " << r << " cos_o " << co;
        }
    EXPECT_TRUE(above_one) << "Burley's rough grazing albedo is expected above 1";
}

// The denoiser's albedo: Burley's diffuse at normal incidence is c, with no (1 - F0).
TEST(BurleyDiffuse, DenoisingAlbedoAtNormalIncidence) {
    Material m = burley(glm::vec3(0.5f, 0.25f, 1.0f), 0.0f, 0.5f);
    m.specular = 0.0f;
    const glm::vec3 a = denoising_albedo(m, flat_point());
    EXPECT_NEAR(a.x, 0.5f, 1e-6f);
    EXPECT_NEAR(a.y, 0.25f, 1e-6f);
    EXPECT_NEAR(a.z, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace librt
