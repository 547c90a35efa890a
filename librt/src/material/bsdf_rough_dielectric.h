#pragma once

// Rough glass (MaterialKind::RoughDielectric): GGX microfacet reflection and transmission
// (Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eqs. 20
// and 21) with the exact dielectric Fresnel, total internal reflection, Smith
// height-correlated G2; a visible normal is sampled (Heitz 2018), then reflection with
// probability F(wo.h) and refraction otherwise, so each sample weighs albedo G2 / G1(wo).
// Like the smooth Dielectric the transmission carries no 1 / eta^2 radiance factor (its
// radiance is that of the symmetric, "importance" form: a closed glass object neither
// gains nor loses energy). Roughness 0 is exactly the smooth Dielectric.

#include "material/bsdf_dielectric.h"
#include "material/microfacet.h"
#include "material/microfacet_anisotropic.h"
#include "material/specular.h"

#include <librt/material/bsdf.h>

#include <cmath>

namespace librt::bsdfs {

struct RoughDielectric {
    static constexpr MaterialKind kKind = MaterialKind::RoughDielectric;
    /// The rough lobes; at roughness 0 they are the smooth Dielectric's.
    static constexpr BsdfLobe kRough =
        BsdfLobe::Glossy | BsdfLobe::Reflection | BsdfLobe::Transmission;
    static constexpr BsdfLobe kLobes = kRough | Dielectric::kLobes;

    static bool transmits(const Material& /*m*/) { return true; }
    static bool near_specular(const Material& m, float limit) { return m.roughness < limit; }
    static bool casts_caustics(const Material& m, float max_roughness) {
        return m.roughness <= max_roughness;
    }
    static void multiply_color(Material& m, const glm::vec3& c) { m.albedo *= c; }
    /// Its tint, as the smooth Dielectric's: reflection and refraction lose nothing but the
    /// microfacets' shadowing, which this colour ignores.
    static glm::vec3 denoising_albedo(const Material& /*m*/, const ShadingPoint& p) {
        return p.albedo;
    }

    /// Roughness 0 without anisotropy: the smooth Dielectric.
    static bool smooth(const Material& m) { return m.roughness <= 0.0f && m.anisotropy <= 0.0f; }

    static BsdfLobe lobes(const Material& m) { return smooth(m) ? Dielectric::kLobes : kRough; }

    /// Index on wi's side of the surface over that on wo's side, for a transmission.
    static float eta_t(const ShadingPoint& p, float ior) {
        return p.frame.front ? ior : 1.0f / ior;
    }

    [[gnu::noinline]] static BsdfSample sample(const Material& m, const ShadingPoint& p,
                                               const glm::vec3& wo, float uc, glm::vec2 u) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::sample_anisotropic<RoughDielectric>(m, p, wo, uc, u);
        if (m.roughness <= 0.0f) return Dielectric::sample(m, p, wo, uc, u);
        if (wo.z <= 0.0f) return {};
        return sample_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo,
                           uc, u);
    }

    /// The rough sample for wo.z > 0, given the lobe.
    template <class Ggx>
    static BsdfSample sample_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                                  const glm::vec3& wo, float uc, glm::vec2 u) {
        const float eta = eta_t(p, m.ior);
        const glm::vec3 h = ggx.sample_visible_normal(wo, u);
        const float oh = glm::dot(wo, h);
        const float f = microfacet::fresnel_dielectric(oh, eta);
        glm::vec3 wi;
        bool transmitted = false;
        if (uc < f) {
            wi = reflect(-wo, h);
        } else {
            const float cos_t = refracted_cos(oh, 1.0f / eta);
            if (cos_t < 0.0f) return {};  // cannot happen when F < 1; guards rounding
            wi = refract(-wo, h, 1.0f / eta, oh, cos_t);
            transmitted = true;
        }
        if (!valid_side(p, wi, transmitted)) return {};
        const float g = ggx.g2(wo, wi) / ggx.g1(wo);
        const BsdfLobe lobe =
            BsdfLobe::Glossy | (transmitted ? BsdfLobe::Transmission : BsdfLobe::Reflection);
        return {wi, p.albedo * g, pdf_with(ggx, m, p, wo, wi), lobe};
    }

    /// wo above the shading normal and wi on a valid side for the lobe its side implies.
    static bool reaches(const ShadingPoint& p, const glm::vec3& wo, const glm::vec3& wi) {
        return wo.z > 0.0f && valid_side(p, wi, wi.z < 0.0f);
    }

    /// Reflection stays above both normals, transmission goes below both.
    static bool valid_side(const ShadingPoint& p, const glm::vec3& wi, bool transmitted) {
        if (wi.z == 0.0f) return false;
        return transmitted ? (wi.z < 0.0f && !p.frame.above_geometry(wi))
                           : (wi.z > 0.0f && p.frame.above_geometry(wi));
    }

    /// The microfacet normal joining wo and wi (on +z), or none (z = 0) for a pair no
    /// microfacet joins.
    static glm::vec3 half_vector(const glm::vec3& wo, const glm::vec3& wi, float eta) {
        const bool transmitted = wi.z < 0.0f;
        // Reflection: wo + wi; refraction: the generalised half vector wo + eta wi
        // (Walter et al. 2007, eq. 16).
        glm::vec3 h = transmitted ? wo + eta * wi : wo + wi;
        const float len = glm::length(h);
        if (!(len > 0.0f)) return glm::vec3(0.0f);
        h /= len;
        if (h.z < 0.0f) h = -h;
        // The microfacet must face wo, and (for refraction) have wi behind it.
        if (glm::dot(wo, h) <= 0.0f) return glm::vec3(0.0f);
        if (transmitted ? glm::dot(wi, h) >= 0.0f : glm::dot(wi, h) <= 0.0f) return glm::vec3(0.0f);
        return h;
    }

    [[gnu::noinline]] static glm::vec3 eval(const Material& m, const ShadingPoint& p,
                                            const glm::vec3& wo, const glm::vec3& wi) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::eval_anisotropic<RoughDielectric>(m, p, wo, wi);
        if (m.roughness <= 0.0f || !reaches(p, wo, wi)) return glm::vec3(0.0f);
        return eval_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo, wi);
    }

    /// A rough lobe narrower than kDeltaLightAlpha (delta_light_material); the smooth one is
    /// a delta lobe that no light sample reaches, and stays so.
    static bool widens_for_delta_light(const Material& m) {
        return !smooth(m) && m.roughness < microfacet::kDeltaLightRoughness;
    }
    [[gnu::noinline]] static float pdf(const Material& m, const ShadingPoint& p,
                                       const glm::vec3& wo, const glm::vec3& wi) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::pdf_anisotropic<RoughDielectric>(m, p, wo, wi);
        if (m.roughness <= 0.0f || !reaches(p, wo, wi)) return 0.0f;
        return pdf_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo, wi);
    }

    /// eval() for wo.z > 0 and wi on a valid side, given the lobe.
    template <class Ggx>
    static glm::vec3 eval_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                               const glm::vec3& wo, const glm::vec3& wi) {
        const float eta = eta_t(p, m.ior);
        const glm::vec3 h = half_vector(wo, wi, eta);
        if (h.z <= 0.0f) return glm::vec3(0.0f);
        const float oh = glm::dot(wo, h), ih = glm::dot(wi, h);
        const float f = microfacet::fresnel_dielectric(oh, eta);
        const float dg = ggx.d(h) * ggx.g2(wo, wi);
        if (wi.z > 0.0f) return p.albedo * (f * dg / (4.0f * wo.z * wi.z));  // eq. 20
        // Walter et al. eq. 21 times (n_o / n_i)^2 (no radiance scaling, see above):
        // (1 - F) D G2 |wi.h| |wo.h| / (|cos_i| cos_o (wi.h + wo.h / eta)^2).
        const float denom = ih + oh / eta;
        return p.albedo *
               ((1.0f - f) * dg * std::fabs(ih) * oh / (std::fabs(wi.z) * wo.z * denom * denom));
    }

    /// pdf() for wo.z > 0 and wi on a valid side, given the lobe.
    template <class Ggx>
    static float pdf_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                          const glm::vec3& wo, const glm::vec3& wi) {
        const float eta = eta_t(p, m.ior);
        const glm::vec3 h = half_vector(wo, wi, eta);
        if (h.z <= 0.0f) return 0.0f;
        const float oh = glm::dot(wo, h), ih = glm::dot(wi, h);
        const float f = microfacet::fresnel_dielectric(oh, eta);
        const float vndf = ggx.vndf_pdf(wo, h);
        if (wi.z > 0.0f) return f * ggx.reflection_pdf(wo, h);
        // Refraction's Jacobian |wi.h| / (wi.h + wo.h / eta)^2 (Walter et al. eq. 17,
        // divided through by eta^2).
        const float denom = ih + oh / eta;
        return (1.0f - f) * vndf * std::fabs(ih) / (denom * denom);
    }
};

}  // namespace librt::bsdfs
