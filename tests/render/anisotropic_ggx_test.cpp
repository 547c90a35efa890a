// Anisotropic GGX (Material::anisotropy, KHR_materials_anisotropy): the distribution
// integrates to 1 over projected area and its visible normals to 1 (the Smith G1
// identity), each against the library's float functions by quadrature; D and Lambda
// equal double-precision formulas written from Heitz 2014; alpha_x == alpha_y is the
// isotropic code; and every rough kind with anisotropy at a rotated direction passes
// chi-square of sample() against pdf() (down to 87 degrees), weight == eval cos / pdf,
// reciprocity, albedo <= 1, and a white conductor's albedo equals an independent quadrature.

#include "material/bsdf_metallic_roughness.h"
#include "material/microfacet_anisotropic.h"
#include "render/anisotropic_ggx_test_util.h"
#include "render/bsdf_chi_square_util.h"
#include "render/microfacet_test_util.h"
#include "sampling/chi_square.h"
#include "sampling/direction_bins.h"
#include "sampling/sanitizer_scale.h"

#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

namespace librt {
namespace {

using microfacet::Alpha2;
using testing::Case;
using testing::flat_point;
using testing::for_each_normal;
using testing::local_dir;
using testing::ref_d;
using testing::ref_lambda;

constexpr double kPi = std::numbers::pi;

/// The alpha pairs under test, (alpha along local x, alpha along local y) after rotation.
const Alpha2 kPairs[] = {{0.05f, 0.3f}, {0.3f, 0.8f}, {0.8f, 0.1f}};

/// KHR_materials_anisotropy's (roughness, strength) for alphas (at, ab), at >= ab:
/// ab = roughness^2, at = ab + (1 - ab) strength^2.
std::pair<float, float> khr_parameters(float at, float ab) {
    return {std::sqrt(ab), std::sqrt((at - ab) / (1.0f - ab))};
}

/// Angle of the anisotropy direction in the flat frame for a pair: a rotation of 0.6 rad,
/// plus pi/2 when alpha_y is the larger (the direction carries alpha_t, the larger one).
double direction_angle(Alpha2 a) { return 0.6 + (a.y > a.x ? 0.5 * kPi : 0.0); }

/// Every rough kind with the anisotropy of `a`, its direction given off the shading plane
/// (the BSDFs project it).
std::vector<Case> anisotropic_cases(Alpha2 a) {
    const auto [roughness, strength] = khr_parameters(std::max(a.x, a.y), std::min(a.x, a.y));
    const double phi = direction_angle(a);
    const std::string tag = " alphas (" + std::to_string(a.x) + ", " + std::to_string(a.y) + ")";
    std::vector<Case> cases = {
        {"gold" + tag, Material::conductor(Metal::Gold, roughness)},
        {"glass outside" + tag, Material::rough_dielectric(1.5f, roughness), true},
        {"glass inside" + tag, Material::rough_dielectric(1.5f, roughness), false},
        {"gltf plastic" + tag, Material::metallic_roughness({0.8f, 0.3f, 0.1f}, 0.0f, roughness)},
        {"gltf half metal" + tag,
         Material::metallic_roughness({0.9f, 0.7f, 0.2f}, 0.5f, roughness, 1.45f)},
        {"gltf transmissive" + tag,
         Material::metallic_roughness({0.9f, 0.9f, 0.8f}, 0.2f, roughness, 1.5f, 0.7f)}};
    for (Case& c : cases) {
        c.material.anisotropy = strength;
        c.material.anisotropy_direction =
            glm::vec3(glm::dvec3(2.0 * std::cos(phi), 2.0 * std::sin(phi), 0.7));
    }
    return cases;
}

TEST(AnisotropicGgx, KhrAlphasAndTheirInverse) {
    for (const Alpha2 a : kPairs) {
        const float at = std::max(a.x, a.y), ab = std::min(a.x, a.y);
        const auto [roughness, strength] = khr_parameters(at, ab);
        const Alpha2 got = microfacet::anisotropic_alphas(roughness, strength);
        EXPECT_NEAR(got.x, at, 1e-6f);
        EXPECT_NEAR(got.y, ab, 1e-6f);
    }
    // Strength 0 is the isotropic alpha; strength 1 makes alpha_t 1.
    EXPECT_EQ(microfacet::anisotropic_alphas(0.5f, 0.0f).x, microfacet::alpha_of(0.5f));
    EXPECT_EQ(microfacet::anisotropic_alphas(0.5f, 1.0f).x, 1.0f);
}

// D and Lambda against the double formulas; integral of D cos = 1 (projected microsurface
// area, Heitz 2014 eq. 4) and of G1(wo) max(0, wo.m) D = cos theta_o (the visible normal
// distribution normalises, Heitz 2014 eq. 17 / Heitz 2018 eq. 2), by quadrature, at
// azimuths along, across and between the axes and incidence down to 89 degrees.
TEST(AnisotropicGgx, DistributionAndVisibleNormalsNormalise) {
    for (const Alpha2 a : kPairs) {
        const double ax = a.x, ay = a.y;
        double area = 0.0;
        for_each_normal(
            ax, ay, 0.0,
            [&](const glm::dvec3& m, double w) {
                const float d = microfacet::ggx_d(glm::vec3(m), a);
                ASSERT_NEAR(d, ref_d(m, ax, ay), 1e-4 * ref_d(m, ax, ay) + 1e-12);
                area += d * m.z * w;
            },
            1000, 400);
        EXPECT_NEAR(area, 1.0, 1e-3) << ax << ", " << ay;
        for (const double co : {0.95, 0.5, 0.1, 0.02})
            for (const double phi : {0.0, 0.7, 1.5707963, 2.6}) {
                const glm::vec3 wo = local_dir(co, phi);
                const double lambda = microfacet::ggx_lambda(wo, a);
                EXPECT_NEAR(lambda, ref_lambda(glm::dvec3(wo), ax, ay), 1e-5 * (1.0 + lambda));
                double visible = 0.0;
                for_each_normal(
                    ax, ay, 0.0,
                    [&](const glm::dvec3& m, double w) {
                        const double om = glm::dot(glm::dvec3(wo), m);
                        if (om > 0.0)
                            visible += microfacet::ggx_g1(wo, a) * om *
                                       microfacet::ggx_d(glm::vec3(m), a) * w;
                    },
                    1000, 400);
                EXPECT_NEAR(visible / wo.z, 1.0, 2e-3)
                    << ax << ", " << ay << " cos_o " << co << " phi " << phi;
            }
    }
}

// alpha_x == alpha_y: the anisotropic D and visible-normal sample are the isotropic code's
// arithmetic (bit for bit), Lambda equal to rounding; the rotated lobe is rotation
// invariant; and a material with anisotropy 0 gives bit-identical results whatever its
// anisotropy direction and rotation say.
TEST(AnisotropicGgx, IsotropicAlphasAreTheIsotropicCode) {
    Pcg32 rng(12, 3);
    for (const float alpha : {0.01f, 0.09f, 0.64f})
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 m = local_dir(rng.next_float(), 6.283 * rng.next_float());
            const glm::vec3 w = local_dir(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
            const glm::vec2 u = rng.next_vec2();
            const Alpha2 a{alpha, alpha};
            ASSERT_EQ(microfacet::ggx_d(m, a), microfacet::ggx_d(m, alpha));
            const glm::vec3 s1 = microfacet::sample_visible_normal(w, a, u);
            const glm::vec3 s0 = microfacet::sample_visible_normal(w, alpha, u);
            ASSERT_EQ(s1, s0);
            const float l0 = microfacet::ggx_lambda(w, alpha);
            ASSERT_NEAR(microfacet::ggx_lambda(w, a), l0, 1e-6f * (1.0f + l0));
            const microfacet::AnisotropicGgx turned{a, std::cos(float(i)), std::sin(float(i))};
            const microfacet::IsotropicGgx iso{alpha};
            ASSERT_NEAR(turned.d(m), iso.d(m), 2e-5f * iso.d(m));
            ASSERT_NEAR(turned.g2(w, m), iso.g2(w, m), 2e-5f);
            // vndf_pdf's w.m loses digits to cancellation near 0: allow its absolute
            // rounding (~1e-7) times the rest of the density.
            ASSERT_NEAR(turned.vndf_pdf(w, m), iso.vndf_pdf(w, m),
                        2e-5f * iso.vndf_pdf(w, m) + 1e-6f * iso.g1(w) * iso.d(m) / w.z);
        }
    for (const Case& c : testing::rough_cases(0.3f)) {
        Material turned = c.material;
        turned.anisotropy_direction = {0.3f, 0.9f, 0.1f};
        turned.anisotropy_rotation = 1.0f;
        const ShadingPoint p = flat_point(c.front);
        for (int i = 0; i < 500; ++i) {
            const glm::vec3 wo = local_dir(rng.next_float(), 6.283 * rng.next_float());
            const glm::vec3 wi = local_dir(2.0 * rng.next_float() - 1.0, 6.283 * rng.next_float());
            const float uc = rng.next_float();
            const glm::vec2 u = rng.next_vec2();
            const BsdfSample s0 = sample(c.material, p, wo, uc, u),
                             s1 = sample(turned, p, wo, uc, u);
            ASSERT_EQ(s0.wi, s1.wi) << c.name;
            ASSERT_EQ(s0.weight, s1.weight) << c.name;
            ASSERT_EQ(s0.pdf, s1.pdf) << c.name;
            ASSERT_EQ(eval(c.material, p, wo, wi), eval(turned, p, wo, wi)) << c.name;
            ASSERT_EQ(pdf(c.material, p, wo, wi), pdf(turned, p, wo, wi)) << c.name;
        }
    }
}

// Weight = f |cos| / pdf with pdf = pdf(), f >= 0, the lobe one of the material's; and
// reciprocity of reflection.
TEST(AnisotropicGgx, SampleWeightEvalPdfAndReciprocity) {
    Pcg32 rng(5, 9);
    for (const Alpha2 a : kPairs)
        for (const Case& c : anisotropic_cases(a)) {
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
            for (int i = 0; i < 5000; ++i) {
                const glm::vec3 x = local_dir(rng.next_float(), 6.283 * rng.next_float());
                const glm::vec3 y = local_dir(rng.next_float(), 6.283 * rng.next_float());
                const glm::vec3 fxy = eval(c.material, p, x, y), fyx = eval(c.material, p, y, x);
                for (int k = 0; k < 3; ++k) {
                    ASSERT_GE(fxy[k], 0.0f) << c.name;
                    ASSERT_NEAR(fxy[k], fyx[k], 1e-4f * fxy[k] + 1e-7f) << c.name;
                }
            }
        }
}

// Chi-square of sample() against pdf(): equal-solid-angle cells over the sphere, expected
// counts pushed forward from microfacet normals (a grid dense where the rotated lobe is)
// through the reflection (and refraction, or thin transmission) of wo, weighted by pdf()
// times the Jacobian d omega_i / d omega_h; one cell for failed samples.
TEST(AnisotropicGgx, SampledDirectionsFollowPdf) {
    // Under a sanitizer a tenth of the samples (sampling/sanitizer_scale.h), and a coarser
    // quadrature to match: a normal's mass lands wholly in one cell, so the expected
    // counts' error is first order in the node spacing. Relative to a count's standard
    // error (1 / sqrt(n p)) it stays the same with the spacing ~ 1 / sqrt(n): nodes per
    // axis in proportion to sqrt(n), nodes in all (the cost) to n.
    const int n = testing::scaled_samples(100'000);
    const double grid = std::sqrt(n / 100'000.0);
    const int n_psi = static_cast<int>(2400 * grid), n_phi = static_cast<int>(960 * grid);
    for (const Alpha2 a : kPairs)
        for (const Case& c : anisotropic_cases(a))
            for (const double co : {0.9, 0.5, 0.2, 0.05}) {
                const ShadingPoint p = flat_point(c.front);
                const glm::vec3 wo = local_dir(co, 0.3);
                testing::DirectionBins bins;
                bins.frame = Frame::from_normal({0, 0, 1});
                Pcg32 rng(std::uint64_t(1000 * a.x + 100 * a.y + 10 * co), 23);
                const std::vector<double> observed =
                    testing::sampled_direction_counts(c.material, p, wo, bins, n, rng);
                std::vector<double> expected(observed.size(), 0.0);
                const bool refracts = c.material.kind == MaterialKind::RoughDielectric;
                const bool thin = c.material.kind == MaterialKind::MetallicRoughness &&
                                  c.material.transmission > 0.0f;
                const double eta = c.front ? 1.5 : 1.0 / 1.5;
                const glm::dvec3 o(wo);
                double integral = 0.0;
                // The glTF kind's cosine lobe is spread too thin over a grid of normals:
                // its share of pdf() (the lobe's probability times cos / pi) is integrated
                // over each cell in closed form, (c1^2 - c0^2) / 2 dphi / pi, and only the
                // rest of pdf() pushed forward.
                const double p_diffuse =
                    c.material.kind == MaterialKind::MetallicRoughness
                        ? bsdfs::MetallicRoughness::lobe_probabilities(c.material, p, wo)[1]
                        : 0.0;
                for (int i = 0; i < bins.n_cos; ++i) {
                    const double c0 = -1.0 + 2.0 * i / bins.n_cos, c1 = c0 + 2.0 / bins.n_cos;
                    if (c0 < 0.0) continue;
                    const double m =
                        p_diffuse * 0.5 * (c1 * c1 - c0 * c0) * (2.0 * kPi / bins.n_phi) / kPi;
                    for (int j = 0; j < bins.n_phi; ++j)
                        expected[std::size_t(i * bins.n_phi + j)] += n * m;
                    integral += m * bins.n_phi;
                }
                // The pair's x alpha lies along direction_angle - (pi/2 if swapped): the
                // grid's axes follow the lobe's (at least 0.05 wide, for its tails).
                const double phi0 = direction_angle(a) - (a.y > a.x ? 0.5 * kPi : 0.0);
                for_each_normal(
                    std::max(0.05, double(a.x)), std::max(0.05, double(a.y)), phi0,
                    [&](const glm::dvec3& h, double node_weight) {
                        const double oh = glm::dot(o, h);
                        if (oh <= 0.0) return;
                        auto add = [&](const glm::dvec3& wi, double jacobian) {
                            const glm::vec3 w(glm::normalize(wi));
                            const double rest =
                                pdf(c.material, p, wo, w) - p_diffuse * std::max(0.0f, w.z) / kPi;
                            const double m = std::max(0.0, rest) * jacobian * node_weight;
                            const int cell = bins.cell(w);
                            if (cell >= 0) expected[std::size_t(cell)] += n * m;
                            integral += m;
                        };
                        // Each h's reflection counts above the surface only, its refraction
                        // or mirrored (thin) reflection below only: elsewhere pdf() is
                        // another lobe's.
                        const glm::dvec3 wr = 2.0 * oh * h - o;
                        if (wr.z > 0.0) add(wr, 4.0 * oh);
                        if (thin && wr.z > 0.0) add({wr.x, wr.y, -wr.z}, 4.0 * oh);
                        if (refracts) {
                            const double s2 = (1.0 - oh * oh) / (eta * eta);
                            if (s2 < 1.0) {
                                const glm::dvec3 wt =
                                    -o / eta + (oh / eta - std::sqrt(1.0 - s2)) * h;
                                const double th = glm::dot(wt, h), den = th + oh / eta;
                                if (wt.z < 0.0) add(wt, den * den / std::fabs(th));
                            }
                        }
                    },
                    n_psi, n_phi);
                EXPECT_LE(integral, 1.003) << c.name << " cos_o " << co;
                expected.back() = std::max(0.0, n - n * integral);
                testing::expect_chi_square_passes(observed, expected,
                                                  c.name + " cos_o " + std::to_string(co));
            }
}

// Directional albedo (mean sampled weight) <= 1 within 4 standard errors (the glTF kind
// only down to cos 0.3, as in Microfacet.DirectionalAlbedoAtMostOne); a white conductor
// (F = 1) reflects exactly the anisotropic GGX single-scattering energy, the integral of
// D G2 (wo.h) / cos_o over h, computed here with the double formulas.
TEST(AnisotropicGgx, AlbedoAtMostOneAndWhiteFurnace) {
    const int n = testing::scaled_samples(100'000);  // a tenth under a sanitizer
    const int n_white = testing::scaled_samples(200'000);
    for (const Alpha2 a : kPairs) {
        for (const Case& c : anisotropic_cases(a))
            for (const double co : {1.0, 0.7, 0.3, 0.05, 0.01}) {
                if (c.material.kind == MaterialKind::MetallicRoughness && co < 0.3) continue;
                const ShadingPoint p = flat_point(c.front);
                const glm::vec3 wo = local_dir(co, 1.0);
                Pcg32 rng(78, 2);
                testing::expect_albedo_at_most_one(c.material, p, wo, n, rng,
                                                   c.name + " cos_o " + std::to_string(co));
            }
        Material white = Material::conductor(glm::vec3(1.0f), glm::vec3(1000.0f), 0.5f);
        white.anisotropy = anisotropic_cases(a)[0].material.anisotropy;
        white.roughness = anisotropic_cases(a)[0].material.roughness;
        white.anisotropy_direction = anisotropic_cases(a)[0].material.anisotropy_direction;
        const double ax = a.x, ay = a.y, phi0 = direction_angle(a) - (a.y > a.x ? 0.5 * kPi : 0.0);
        for (const double co : {0.95, 0.5, 0.1})
            for (const double phi : {0.3, 1.9}) {
                const glm::vec3 wo = local_dir(co, phi);
                // wo in the lobe's frame, where the double formulas' axes are.
                const glm::dvec3 o(wo), ol(std::cos(phi0) * o.x + std::sin(phi0) * o.y,
                                           std::cos(phi0) * o.y - std::sin(phi0) * o.x, o.z);
                const double expected = testing::ref_anisotropic_albedo(ol, ax, ay);
                Pcg32 rng(4, 4);
                double sum = 0.0, sum2 = 0.0;
                for (int i = 0; i < n_white; ++i) {
                    const BsdfSample s = sample(white, flat_point(), wo, 0.5f, rng.next_vec2());
                    const double w = s.valid() ? s.weight.x : 0.0;
                    sum += w;
                    sum2 += w * w;
                }
                const double mean = sum / n_white,
                             se = std::sqrt((sum2 / n_white - mean * mean) / n_white);
                EXPECT_LE(expected, 1.0 + 1e-3);
                EXPECT_NEAR(mean, expected, 5.0 * se + 2e-4)
                    << ax << ", " << ay << " cos_o " << co << " phi " << phi;
            }
    }
}

}  // namespace
}  // namespace librt
