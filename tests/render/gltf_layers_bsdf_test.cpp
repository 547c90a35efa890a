// The lobes the glTF material extensions add to the metallic-roughness BSDF
// (KHR_materials_clearcoat, KHR_materials_sheen, KHR_materials_specular): sample() agrees
// with eval() and pdf(); reciprocity; chi-square of sampled directions against pdf();
// directional albedo <= 1; at their defaults they change nothing; a coat with its own normal
// (clearcoatNormalTexture) is the coat lobe in that normal's frame; closed forms: with
// specularFactor 0 a white base is exactly Lambertian (a white furnace returns 1), and a
// sheen over a black base reflects its tabulated albedo E(cos_o), checked against the
// test's own double-precision quadrature of Estevez & Kulla's D and Neubelt's V.

#include "material/sheen.h"
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

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace librt {
namespace {

using testing::Case;
using testing::flat_point;
using testing::local_dir;

/// A material with a clear coat, one with a sheen, one with the specular extension, and
/// all three over a half-metal with transmission, at base roughness r.
std::vector<Case> layered_cases(float r) {
    const std::string s = " r=" + std::to_string(r);
    Material coat = Material::metallic_roughness({0.7f, 0.1f, 0.1f}, 0.0f, r);
    coat.clearcoat = 1.0f;
    coat.clearcoat_roughness = 0.3f;
    Material sheen = Material::metallic_roughness({0.2f, 0.3f, 0.8f}, 0.0f, r);
    sheen.sheen_color = {1.0f, 0.8f, 0.6f};
    sheen.sheen_roughness = 0.5f;
    Material specular = Material::metallic_roughness({0.6f, 0.6f, 0.2f}, 0.0f, r);
    specular.specular = 0.6f;
    specular.specular_color = {2.0f, 1.0f, 0.5f};
    Material all = Material::metallic_roughness({0.9f, 0.8f, 0.7f}, 0.3f, r, 1.5f, 0.4f);
    all.clearcoat = 0.6f;
    all.clearcoat_roughness = 0.6f;
    all.sheen_color = {0.5f, 0.5f, 0.5f};
    all.sheen_roughness = 0.8f;
    all.specular = 0.8f;
    all.specular_color = {1.0f, 1.5f, 1.0f};
    return {{"clearcoat" + s, coat},
            {"sheen" + s, sheen},
            {"specular" + s, specular},
            {"all layers" + s, all}};
}

constexpr float kRoughness[] = {0.05f, 0.3f, 0.8f};

TEST(GltfLayers, SampleWeightIsEvalCosOverPdf) {
    Pcg32 rng(5, 13);
    for (const float r : kRoughness)
        for (const Case& c : layered_cases(r)) {
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

TEST(GltfLayers, ReflectionIsReciprocalAndNonNegative) {
    Pcg32 rng(9, 2);
    for (const float r : kRoughness)
        for (const Case& c : layered_cases(r)) {
            const ShadingPoint p = flat_point(c.front);
            for (int i = 0; i < 5000; ++i) {
                const glm::vec3 a = local_dir(rng.next_float(), 6.283 * rng.next_float());
                const glm::vec3 b = local_dir(rng.next_float(), 6.283 * rng.next_float());
                const glm::vec3 fab = eval(c.material, p, a, b), fba = eval(c.material, p, b, a);
                const glm::vec3 ft = eval(c.material, p, a, -b), ftr = eval(c.material, p, b, -a);
                for (int k = 0; k < 3; ++k) {
                    ASSERT_GE(fab[k], 0.0f) << c.name;
                    ASSERT_GE(ft[k], 0.0f) << c.name;
                    ASSERT_TRUE(std::isfinite(ft[k])) << c.name;
                    ASSERT_NEAR(fab[k], fba[k], 1e-4f * fab[k] + 1e-7f) << c.name;
                    ASSERT_NEAR(ft[k], ftr[k], 1e-4f * ft[k] + 1e-7f) << c.name;
                }
            }
        }
}

// Chi-square over equal-solid-angle cells of the whole sphere (expected counts by
// Gauss-Legendre quadrature of pdf()), plus a cell for failed samples holding 1 minus the
// integral of pdf. Base roughness 0.3 and 0.8 (the coat's 0.3 or 0.6), incidence down to
// 78 degrees; the coat of roughness 0.3 (alpha 0.09) only to 60: at 78 degrees its lobe is
// too narrow for this quadrature of pdf() over the cells (as Microfacet.
// SampledDirectionsFollowPdf says of narrow lobes), and sample() agreeing with pdf()
// there is checked pointwise by SampleWeightIsEvalCosOverPdf.
TEST(GltfLayers, SampledDirectionsFollowPdf) {
    const int n = testing::scaled_samples(100'000);
    for (const float r : {0.3f, 0.8f})
        for (const Case& c : layered_cases(r))
            for (const double co : {0.9, 0.5, 0.2}) {
                if (c.material.clearcoat_roughness < 0.5f && c.material.clearcoat > 0.0f &&
                    co < 0.5)
                    continue;
                const ShadingPoint p = flat_point(c.front);
                const glm::vec3 wo = local_dir(co, 0.3);
                Pcg32 rng(uint64_t(1000 * r + 10 * co), 7);
                testing::expect_sampling_follows_pdf(c.material, p, wo, n, rng,
                                                     c.name + " cos_o " + std::to_string(co));
            }
}

// Directional albedo <= 1 within 4 standard errors on white bases, down to cos_o 0.7: at
// 0.3 and below the glTF base itself exceeds 1 on a white base (its fresnel_mix weighs
// the diffuse by 1 - F(V.H) per direction; Microfacet.DirectionalAlbedoAtMostOne, with a
// coloured base, stops at 0.3 for the same reason).
TEST(GltfLayers, DirectionalAlbedoAtMostOne) {
    const int n = testing::scaled_samples(50'000);
    for (const float r : kRoughness)
        for (Case c : layered_cases(r))
            for (const double co : {1.0, 0.7}) {
                // White bases, the harder case for the bound.
                c.material.base_color = glm::vec3(1.0f);
                const ShadingPoint p = flat_point(c.front);
                Pcg32 rng(31, 4);
                testing::expect_albedo_at_most_one(c.material, p, local_dir(co, 1.0), n, rng,
                                                   c.name + " cos_o " + std::to_string(co));
            }
}

// At their defaults the extensions' fields leave every value of the BSDF as it was: the
// material with the defaults set explicitly against one without (same bits).
TEST(GltfLayers, DefaultsChangeNothing) {
    Material plain = Material::metallic_roughness({0.5f, 0.4f, 0.3f}, 0.2f, 0.4f, 1.5f, 0.3f);
    Material zeroed = plain;
    zeroed.clearcoat = 0.0f;
    zeroed.clearcoat_roughness = 0.7f;  // without a coat, its roughness does nothing
    zeroed.sheen_roughness = 0.4f;      // nor the sheen's without its colour
    zeroed.specular = 1.0f;
    zeroed.specular_color = glm::vec3(1.0f);
    const ShadingPoint p = flat_point();
    Pcg32 rng(4, 4);
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 wo = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 wi = local_dir(2.0 * rng.next_float() - 1.0, 6.283 * rng.next_float());
        ASSERT_EQ(eval(plain, p, wo, wi), eval(zeroed, p, wo, wi));
        ASSERT_EQ(pdf(plain, p, wo, wi), pdf(zeroed, p, wo, wi));
    }
}

// specularFactor 0 removes the dielectric's specular layer: a white base is then exactly
// Lambertian, f = 1 / pi everywhere above the surface, and its albedo (a white furnace
// with one bounce) is 1 at every angle.
TEST(GltfLayers, SpecularZeroIsLambertianWhiteFurnace) {
    Material m = Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.4f);
    m.specular = 0.0f;
    const ShadingPoint p = flat_point();
    Pcg32 rng(6, 1);
    for (int i = 0; i < 1000; ++i) {
        const glm::vec3 wo = local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 wi = local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 f = eval(m, p, wo, wi);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(f[k], 1.0 / std::numbers::pi, 1e-6) << i;
    }
    for (const double co : {1.0, 0.5, 0.1, 0.02}) {
        const glm::vec3 wo = local_dir(co, 0.2);
        double sum = 0.0, sum2 = 0.0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
            const BsdfSample s = sample(m, p, wo, rng.next_float(), rng.next_vec2());
            const double w = s.valid() ? double(s.weight.x) : 0.0;
            sum += w;
            sum2 += w * w;
        }
        // The weights f cos / pdf of the mixture (the weightless specular lobe keeps a
        // share of the samples) average to the albedo, 1.
        const double mean = sum / n;
        const double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, 1.0, 4.0 * se + 1e-4) << "cos_o " << co;
    }
}

/// The sheen's albedo E(cos_o) by the test's own quadrature in double over (cos_i, phi),
/// from the formulas of Estevez & Kulla 2017 (D) and Neubelt & Pettineo 2013 (V).
double ref_sheen_albedo(double co, double roughness) {
    const double a = std::max(roughness * roughness, 1e-3);
    const double so = std::sqrt(1.0 - co * co);
    const int nc = 400, np = 200;
    double sum = 0.0;
    for (int i = 0; i < nc; ++i) {
        const double ci = (i + 0.5) / nc, si = std::sqrt(1.0 - ci * ci);
        for (int j = 0; j < np; ++j) {
            const double phi = 2.0 * std::numbers::pi * (j + 0.5) / np;
            const double hx = so + si * std::cos(phi), hy = si * std::sin(phi), hz = co + ci;
            const double ch = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
            const double d =
                (2.0 + 1.0 / a) * std::pow(1.0 - ch * ch, 0.5 / a) / (2.0 * std::numbers::pi);
            const double v = 1.0 / (4.0 * (ci + co - ci * co));
            sum += d * v * ci;
        }
    }
    return sum * 2.0 * std::numbers::pi / (nc * np);
}

// A white sheen over a black, non-specular base reflects the sheen alone: its sampled
// albedo equals E(cos_o) of the test's quadrature (within 4 standard errors plus the
// table's interpolation, 2 %), and the library's table agrees with that quadrature.
TEST(GltfLayers, SheenOverBlackReflectsItsAlbedo) {
    const int n = testing::scaled_samples(100'000);
    for (const float rough : {0.3f, 0.6f, 1.0f})
        for (const double co : {1.0, 0.6, 0.3}) {
            Material m = Material::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.5f);
            m.specular = 0.0f;
            m.sheen_color = glm::vec3(1.0f);
            m.sheen_roughness = rough;
            const double e = ref_sheen_albedo(co, rough);
            EXPECT_NEAR(microfacet::sheen_albedo(float(co), rough), e, 0.02 * e + 1e-3)
                << "roughness " << rough << " cos_o " << co;
            EXPECT_LE(e, 1.0);
            const ShadingPoint p = flat_point();
            const glm::vec3 wo = local_dir(co, 0.7);
            Pcg32 rng(12, 3);
            double sum = 0.0, sum2 = 0.0;
            for (int i = 0; i < n; ++i) {
                const BsdfSample s = sample(m, p, wo, rng.next_float(), rng.next_vec2());
                const double w = s.valid() ? double(s.weight.x) : 0.0;
                sum += w;
                sum2 += w * w;
            }
            const double mean = sum / n;
            const double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
            EXPECT_NEAR(mean, e, 4.0 * se + 0.02 * e) << "roughness " << rough << " cos_o " << co;
        }
}

// A full coat over a perfectly black base (specularFactor 0) reflects only the coat:
// f = Fc(|V.H|) D V of GGX at the coat's roughness, against the test's formula.
TEST(GltfLayers, CoatOverBlackIsTheCoatLobe) {
    Material m = Material::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.5f);
    m.specular = 0.0f;
    m.clearcoat = 1.0f;
    m.clearcoat_roughness = 0.5f;
    const double a = 0.25;
    const ShadingPoint p = flat_point();
    Pcg32 rng(2, 9);
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec3 wo(local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float()));
        const glm::dvec3 wi(local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float()));
        const glm::dvec3 h = glm::normalize(wo + wi);
        const double a2 = a * a;
        const double t = h.z * h.z * (a2 - 1.0) + 1.0;
        const double d = a2 / (std::numbers::pi * t * t);
        const auto lambda = [&](const glm::dvec3& w) {
            const double tan2 = (1.0 - w.z * w.z) / (w.z * w.z);
            return 0.5 * (std::sqrt(1.0 + a2 * tan2) - 1.0);
        };
        const double g2 = 1.0 / (1.0 + lambda(wo) + lambda(wi));
        const double fc = 0.04 + 0.96 * std::pow(1.0 - std::fabs(glm::dot(wo, h)), 5.0);
        const double expected = fc * d * g2 / (4.0 * wo.z * wi.z);
        const glm::vec3 f = eval(m, p, glm::vec3(wo), glm::vec3(wi));
        ASSERT_NEAR(f.x, expected, 2e-4 * expected + 1e-7) << i;
    }
}

/// A coat normal tilted by `degrees` from the shading normal (+z), toward azimuth phi.
glm::vec3 tilted(double degrees, double phi) {
    const double t = degrees * std::numbers::pi / 180.0;
    return glm::vec3(float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)),
                     float(std::cos(t)));
}

/// clearcoatNormalTexture: coats whose own normal is tilted from the base's, over a
/// coloured base, a half-metal with transmission and sheen, and a black non-specular base.
std::vector<Case> bent_coat_cases() {
    Material coat = Material::metallic_roughness({0.7f, 0.1f, 0.1f}, 0.0f, 0.5f);
    coat.clearcoat = 1.0f;
    coat.clearcoat_roughness = 0.6f;
    coat.clearcoat_normal = tilted(25.0, 0.4);
    Material all = Material::metallic_roughness({0.9f, 0.8f, 0.7f}, 0.3f, 0.8f, 1.5f, 0.4f);
    all.clearcoat = 0.6f;
    all.clearcoat_roughness = 0.6f;
    all.sheen_color = {0.5f, 0.5f, 0.5f};
    all.sheen_roughness = 0.8f;
    all.clearcoat_normal = tilted(40.0, 2.0);
    Material black = Material::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.5f);
    black.specular = 0.0f;
    black.clearcoat = 1.0f;
    black.clearcoat_roughness = 0.7f;
    black.clearcoat_normal = tilted(30.0, -1.0);
    // A back hit: the frame (and the coat normal with it) turned to wo's side.
    Material back = coat;
    back.clearcoat_normal = -tilted(20.0, 1.0);
    return {{"bent coat", coat},
            {"bent coat, all layers", all},
            {"bent coat over black", black},
            {"bent coat, back", back, false}};
}

// The coat's own normal: sample() agrees with eval() and pdf() (weights f cos / pdf), and
// f and pdf are finite and non-negative everywhere.
TEST(GltfLayers, BentCoatSampleWeightIsEvalCosOverPdf) {
    Pcg32 rng(8, 21);
    for (const Case& c : bent_coat_cases()) {
        const ShadingPoint p = flat_point(c.front);
        int valid = 0, coat_side = 0;
        for (int i = 0; i < 20000; ++i) {
            const glm::vec3 wo =
                local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
            const BsdfSample s = sample(c.material, p, wo, rng.next_float(), rng.next_vec2());
            if (!s.valid()) continue;
            ++valid;
            // The coat's normal as the BSDF turns it: to the geometric normal's side (+z).
            const glm::vec3 nc = c.material.clearcoat_normal.z < 0.0f ? -c.material.clearcoat_normal
                                                                      : c.material.clearcoat_normal;
            coat_side += glm::dot(s.wi, nc) > 0.0f;
            ASSERT_TRUE(testing::sample_agrees_with_eval_pdf(c.material, p, wo, s)) << c.name;
        }
        EXPECT_GT(valid, 10000) << c.name;
        EXPECT_GT(coat_side, 0) << c.name;
    }
}

// Chi-square of sampled directions against pdf() with the coat's normal tilted (the
// failed-sample cell holds the coat's reflections under its own normal or the surface).
TEST(GltfLayers, BentCoatSampledDirectionsFollowPdf) {
    const int n = testing::scaled_samples(100'000);
    for (const Case& c : bent_coat_cases())
        for (const double co : {0.9, 0.5, 0.2}) {
            const ShadingPoint p = flat_point(c.front);
            const glm::vec3 wo = local_dir(co, 0.3);
            Pcg32 rng(uint64_t(100 * co) + 17, 9);
            testing::expect_sampling_follows_pdf(c.material, p, wo, n, rng,
                                                 c.name + " cos_o " + std::to_string(co));
        }
}

// Energy: directional albedo <= 1 (4 standard errors) with the coat's normal tilted, on
// white bases, down to cos_o 0.7 as DirectionalAlbedoAtMostOne.
TEST(GltfLayers, BentCoatDirectionalAlbedoAtMostOne) {
    const int n = testing::scaled_samples(50'000);
    for (Case c : bent_coat_cases())
        for (const double co : {1.0, 0.7}) {
            if (c.material.specular > 0.0f) c.material.base_color = glm::vec3(1.0f);
            const ShadingPoint p = flat_point(c.front);
            Pcg32 rng(33, 5);
            testing::expect_albedo_at_most_one(c.material, p, local_dir(co, 1.0), n, rng,
                                               c.name + " cos_o " + std::to_string(co));
        }
}

// Over a black base the bent coat is exactly the coat lobe of CoatOverBlackIsTheCoatLobe
// turned into its normal's frame, carrying its own cosine: f (wi.z) = f_c(wo', wi')
// (wi'.z) with w' = w in the frame of n_c, and f_c is then reciprocal (f_c(wo', wi') =
// f_c(wi', wo')); zero where wo or wi is under the coat's normal.
TEST(GltfLayers, BentCoatOverBlackIsTheCoatLobeInItsFrame) {
    Material m = Material::metallic_roughness(glm::vec3(0.0f), 0.0f, 0.5f);
    m.specular = 0.0f;
    m.clearcoat = 1.0f;
    m.clearcoat_roughness = 0.5f;
    Material flat = m;
    m.clearcoat_normal = tilted(35.0, 0.8);
    const Frame coat = Frame::from_normal(m.clearcoat_normal);
    const ShadingPoint p = flat_point();
    Pcg32 rng(6, 6);
    int checked = 0, zero = 0;
    for (int i = 0; i < 4000; ++i) {
        const glm::vec3 wo = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 wi = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 wo_c = coat.to_local(wo), wi_c = coat.to_local(wi);
        const float f = eval(m, p, wo, wi).x;
        if (wo_c.z <= 0.02f || wi_c.z <= 0.02f) {
            if (wo_c.z <= 0.0f || wi_c.z <= 0.0f) {
                ASSERT_EQ(f, 0.0f) << i;
                ++zero;
            }
            continue;
        }
        const double expected = double(eval(flat, p, wo_c, wi_c).x) * wi_c.z / wi.z;
        ASSERT_NEAR(f, expected, 1e-4 * expected + 1e-7) << i;
        const float f_c = f * wi.z / wi_c.z;
        const float f_c_reverse = eval(m, p, wi, wo).x * wo.z / wo_c.z;
        ASSERT_NEAR(f_c, f_c_reverse, 1e-4f * f_c + 1e-7f) << i;
        ++checked;
    }
    EXPECT_GT(checked, 1000);
    EXPECT_GT(zero, 100);
}

// Bent to the shading normal itself, the coat normal changes nothing (same bits as unset).
TEST(GltfLayers, CoatNormalAlongTheShadingNormalChangesNothing) {
    Material plain = Material::metallic_roughness({0.5f, 0.4f, 0.3f}, 0.2f, 0.4f);
    plain.clearcoat = 0.8f;
    plain.clearcoat_roughness = 0.3f;
    Material along = plain;
    along.clearcoat_normal = {0.0f, 0.0f, 2.0f};  // not unit: normalised by the BSDF
    const ShadingPoint p = flat_point();
    Pcg32 rng(3, 3);
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 wo = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 wi = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 a = eval(plain, p, wo, wi), b = eval(along, p, wo, wi);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(a[k], b[k], 1e-5f * a[k] + 1e-8f) << i;
        ASSERT_NEAR(pdf(plain, p, wo, wi), pdf(along, p, wo, wi),
                    1e-5f * pdf(plain, p, wo, wi) + 1e-8f);
    }
}

TEST(GltfLayers, ValidateRefusesOutOfRangeFactors) {
    Material m = Material::metallic_roughness(glm::vec3(0.5f), 0.0f, 0.5f);
    m.clearcoat = 1.5f;
    EXPECT_THROW(validate(m), Error);
    m.clearcoat = 1.0f;
    m.specular_color = glm::vec3(-1.0f);
    EXPECT_THROW(validate(m), Error);
    m.specular_color = glm::vec3(3.0f);  // > 1 is allowed (F0 is clamped)
    EXPECT_NO_THROW(validate(m));
    m.sheen_color = glm::vec3(1.2f);
    EXPECT_THROW(validate(m), Error);
    m.sheen_color = glm::vec3(0.5f);
    m.unlit = true;  // only an Emissive material is unlit
    EXPECT_THROW(validate(m), Error);
    m.unlit = false;
    m.clearcoat_normal = glm::vec3(0.0f, std::nanf(""), 1.0f);
    EXPECT_THROW(validate(m), Error);
    m.clearcoat_normal = glm::vec3(0.0f);
    m.clearcoat_normal_scale = std::numeric_limits<float>::infinity();
    EXPECT_THROW(validate(m), Error);
}

}  // namespace
}  // namespace librt
