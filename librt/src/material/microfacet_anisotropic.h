#pragma once

// Anisotropic GGX: the distribution with one roughness along the surface's anisotropy
// direction (alpha_x) and another across it (alpha_y), its Smith Lambda and its visible
// normal sampling, and the lobe types the rough BSDFs are written against
// (IsotropicGgx: the functions of microfacet.h unchanged; AnisotropicGgx: these, in a
// frame turned about the normal so that its x axis is the anisotropy direction), and the
// one out-of-line anisotropic sample / eval / pdf of those BSDFs (templates over the kind).
// Local shading frame as in microfacet.h: +z is the macro normal. Formulas from Heitz
// 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs" (JCGT
// 3(2)), and Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)).

#include "material/microfacet.h"

#include <librt/material/bsdf.h>
#include <librt/material/material.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace librt::microfacet {

/// The two roughnesses of an anisotropic lobe: x along the anisotropy direction.
struct Alpha2 {
    float x = 1.0f;  ///< alpha along the local x axis (KHR_materials_anisotropy's alpha_t)
    float y = 1.0f;  ///< alpha along the local y axis (alpha_b)
};

/// The roughnesses of KHR_materials_anisotropy: alpha_t = mix(alpha, 1, strength^2) along
/// the anisotropy direction, alpha_b = alpha across it, alpha = roughness^2 clamped as
/// alpha_of (the extension's "Implementation" section).
[[nodiscard]] inline Alpha2 anisotropic_alphas(float roughness, float strength) {
    const float a = alpha_of(roughness);
    const float s2 = strength * strength;
    return {a + (1.0f - a) * s2, a};
}

/// Anisotropic GGX D(m) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2) for m.z > 0 (Heitz
/// 2014, eq. 85, in Cartesian form). Written as ax ay / (pi t^2) with t = ax ay z^2 +
/// (ay/ax) x^2 + (ax/ay) y^2: with ax == ay this is ggx_d's arithmetic exactly.
[[nodiscard]] inline float ggx_d(const glm::vec3& m, Alpha2 a) {
    if (m.z <= 0.0f) return 0.0f;
    const float axy = a.x * a.y;
    const float t = axy * m.z * m.z + (a.y / a.x * (m.x * m.x) + a.x / a.y * (m.y * m.y));
    return axy / (kPi * t * t);
}

/// Anisotropic Smith Lambda: (sqrt(1 + (ax^2 x^2 + ay^2 y^2) / z^2) - 1) / 2 (Heitz 2014,
/// eqs. 80 and 86: the isotropic Lambda with alpha_o^2 = cos^2 phi ax^2 + sin^2 phi ay^2).
[[nodiscard]] inline float ggx_lambda(const glm::vec3& w, Alpha2 a) {
    const float c2 = w.z * w.z;
    if (c2 <= 0.0f) return 1e30f;
    const float x = a.x * w.x, y = a.y * w.y;
    return 0.5f * (std::sqrt(1.0f + (x * x + y * y) / c2) - 1.0f);
}

/// Smith masking G1(w) = 1 / (1 + Lambda(w)) (Heitz 2014, eq. 43).
[[nodiscard]] inline float ggx_g1(const glm::vec3& w, Alpha2 a) {
    return 1.0f / (1.0f + ggx_lambda(w, a));
}

/// Height-correlated G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, eq. 99).
[[nodiscard]] inline float ggx_g2(const glm::vec3& wo, const glm::vec3& wi, Alpha2 a) {
    return 1.0f / (1.0f + ggx_lambda(wo, a) + ggx_lambda(wi, a));
}

/// A visible normal of the anisotropic distribution seen from wo (wo.z > 0): microfacet.h's
/// Heitz 2018 sampler with its two roughnesses.
[[nodiscard]] inline glm::vec3 sample_visible_normal(const glm::vec3& wo, Alpha2 a, glm::vec2 u) {
    return sample_visible_normal(wo, a.x, a.y, u);
}

/// Density of the anisotropic sample_visible_normal: G1(wo) max(0, wo.m) D(m) / wo.z
/// (Heitz 2018, eq. 3).
[[nodiscard]] inline float vndf_pdf(const glm::vec3& wo, const glm::vec3& m, Alpha2 a) {
    const float om = glm::dot(wo, m);
    if (om <= 0.0f || wo.z <= 0.0f) return 0.0f;
    return ggx_g1(wo, a) * om * ggx_d(m, a) / wo.z;
}

/// An isotropic GGX lobe: microfacet.h's functions of one alpha, in the shading frame as
/// it is. The rough BSDFs are written against this interface and AnisotropicGgx's.
struct IsotropicGgx {
    float alpha;  ///< GGX alpha

    [[nodiscard]] float d(const glm::vec3& m) const { return ggx_d(m, alpha); }
    [[nodiscard]] float g1(const glm::vec3& w) const { return ggx_g1(w, alpha); }
    [[nodiscard]] float g2(const glm::vec3& wo, const glm::vec3& wi) const {
        return ggx_g2(wo, wi, alpha);
    }
    [[nodiscard]] glm::vec3 sample_visible_normal(const glm::vec3& wo, glm::vec2 u) const {
        return microfacet::sample_visible_normal(wo, alpha, u);
    }
    [[nodiscard]] float vndf_pdf(const glm::vec3& wo, const glm::vec3& m) const {
        return microfacet::vndf_pdf(wo, m, alpha);
    }
    /// vndf_pdf / (4 wo.h): the density of the reflected direction (Walter et al. 2007, eq. 14).
    [[nodiscard]] float reflection_pdf(const glm::vec3& wo, const glm::vec3& h) const {
        return microfacet::reflection_pdf(wo, h, alpha);
    }
};

/// An anisotropic GGX lobe whose alpha.x lies along the shading frame's direction
/// (c, s, 0): every direction is turned by -phi about +z into the lobe's own frame
/// (x' = c x + s y, y' = c y - s x) before the Alpha2 functions see it, and sampled
/// normals are turned back. A turn about the normal keeps z and every dot product, so
/// the BSDFs' Fresnel, Jacobians and side tests need no change.
struct AnisotropicGgx {
    Alpha2 alpha;    ///< alpha.x along (c, s, 0), alpha.y across it
    float c = 1.0f;  ///< cos phi of the anisotropy direction in the shading frame
    float s = 0.0f;  ///< sin phi

    /// Shading frame to the lobe's frame.
    [[nodiscard]] glm::vec3 to_lobe(const glm::vec3& v) const {
        return {c * v.x + s * v.y, c * v.y - s * v.x, v.z};
    }
    /// The lobe's frame to the shading frame.
    [[nodiscard]] glm::vec3 from_lobe(const glm::vec3& v) const {
        return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
    }
    [[nodiscard]] float d(const glm::vec3& m) const { return ggx_d(to_lobe(m), alpha); }
    [[nodiscard]] float g1(const glm::vec3& w) const { return ggx_g1(to_lobe(w), alpha); }
    [[nodiscard]] float g2(const glm::vec3& wo, const glm::vec3& wi) const {
        return ggx_g2(to_lobe(wo), to_lobe(wi), alpha);
    }
    [[nodiscard]] glm::vec3 sample_visible_normal(const glm::vec3& wo, glm::vec2 u) const {
        return from_lobe(microfacet::sample_visible_normal(to_lobe(wo), alpha, u));
    }
    [[nodiscard]] float vndf_pdf(const glm::vec3& wo, const glm::vec3& m) const {
        return microfacet::vndf_pdf(to_lobe(wo), to_lobe(m), alpha);
    }
    /// vndf_pdf / (4 wo.h): the density of the reflected direction (Walter et al. 2007, eq. 14).
    [[nodiscard]] float reflection_pdf(const glm::vec3& wo, const glm::vec3& h) const {
        const float om = glm::dot(wo, h);
        return om > 0.0f ? vndf_pdf(wo, h) / (4.0f * om) : 0.0f;
    }
};

/// The anisotropic lobe of a material at a point: KHR_materials_anisotropy's alphas
/// (anisotropic_alphas) along Material::anisotropy_direction, a world direction projected
/// into the shading frame's tangent plane (the frame's own x axis when it is zero or
/// along the normal). Only for m.anisotropy > 0.
///
/// How the rough BSDFs use it: their sample / eval / pdf are out of line (gnu::noinline)
/// and test m.anisotropy > 0 first, handing anisotropic materials to the cold functions
/// below (sample_anisotropic, eval_anisotropic, pdf_anisotropic); the
/// isotropic code after that test is the code from before anisotropy existed. Why out of
/// line: the path loop inlines every BSDF, and with the anisotropic code (even only its
/// branches and calls) inlined there g++ stopped inlining the loop's own helpers
/// (callgrind on the synthesis, which has no rough material: +0.3 to +0.5 % instructions);
/// with these three kinds out of line it counts 0.03 % fewer than before.
[[nodiscard]] inline AnisotropicGgx anisotropic_lobe(const Material& m, const ShadingPoint& p) {
    AnisotropicGgx g;
    g.alpha = anisotropic_alphas(m.roughness, m.anisotropy);
    const float x = glm::dot(m.anisotropy_direction, p.frame.shading.t);
    const float y = glm::dot(m.anisotropy_direction, p.frame.shading.b);
    const float len = std::sqrt(x * x + y * y);
    if (len > 1e-12f && std::isfinite(len)) {
        g.c = x / len;
        g.s = y / len;
    }
    return g;
}

// The anisotropic sample / eval / pdf of a rough BSDF `Kind` (Conductor, RoughDielectric,
// MetallicRoughness), written once: Kind's sample_with / eval_with / pdf_with given the
// material's AnisotropicGgx, behind Kind's side test reaches(p, wo, wi). Each kind's
// sample / eval / pdf hand a material with anisotropy > 0 to these, out of line and cold
// (see anisotropic_lobe for why).

/// Kind's sample() for an anisotropic material.
template <class Kind>
[[nodiscard, gnu::noinline, gnu::cold]] BsdfSample sample_anisotropic(const Material& m,
                                                                      const ShadingPoint& p,
                                                                      const glm::vec3& wo, float uc,
                                                                      glm::vec2 u) {
    if (wo.z <= 0.0f) return {};
    return Kind::sample_with(anisotropic_lobe(m, p), m, p, wo, uc, u);
}

/// Kind's eval() for an anisotropic material.
template <class Kind>
[[nodiscard, gnu::noinline, gnu::cold]] glm::vec3 eval_anisotropic(const Material& m,
                                                                   const ShadingPoint& p,
                                                                   const glm::vec3& wo,
                                                                   const glm::vec3& wi) {
    if (!Kind::reaches(p, wo, wi)) return glm::vec3(0.0f);
    return Kind::eval_with(anisotropic_lobe(m, p), m, p, wo, wi);
}

/// Kind's pdf() for an anisotropic material.
template <class Kind>
[[nodiscard, gnu::noinline, gnu::cold]] float pdf_anisotropic(const Material& m,
                                                              const ShadingPoint& p,
                                                              const glm::vec3& wo,
                                                              const glm::vec3& wi) {
    if (!Kind::reaches(p, wo, wi)) return 0.0f;
    return Kind::pdf_with(anisotropic_lobe(m, p), m, p, wo, wi);
}

}  // namespace librt::microfacet
