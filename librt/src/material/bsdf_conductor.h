#pragma once

// The rough conductor (MaterialKind::Conductor): GGX microfacet reflection with Smith
// height-correlated masking-shadowing and the exact conductor Fresnel of a complex index
// (eta + i k per channel), f = F(wo.h) D(h) G2(wo, wi) / (4 cos_o cos_i) (Walter et al.
// 2007, eq. 20), sampled by visible normals (Heitz 2018). Roughness 0 is a smooth mirror
// with the same Fresnel. Material::albedo is a tint over everything (1 by default).
// Anisotropic when Material::anisotropy > 0 (microfacet_anisotropic.h).

#include "material/microfacet.h"
#include "material/microfacet_anisotropic.h"
#include "material/specular.h"

#include <librt/material/bsdf.h>

namespace librt::bsdfs {

struct Conductor {
    static constexpr MaterialKind kKind = MaterialKind::Conductor;
    /// The rough lobe; at roughness 0 it is a specular reflection.
    static constexpr BsdfLobe kRough = BsdfLobe::Glossy | BsdfLobe::Reflection;
    static constexpr BsdfLobe kLobes = kRough | BsdfLobe::Specular;

    static bool transmits(const Material& /*m*/) { return false; }
    static bool near_specular(const Material& m, float limit) { return m.roughness < limit; }
    static bool casts_caustics(const Material& m, float max_roughness) {
        return m.roughness <= max_roughness;
    }
    static void multiply_color(Material& m, const glm::vec3& c) { m.albedo *= c; }
    /// Its reflectance at normal incidence, the exact Fresnel of eta + i k at cos = 1, tinted.
    static glm::vec3 denoising_albedo(const Material& m, const ShadingPoint& p) {
        return p.albedo * microfacet::fresnel_conductor(1.0f, m.eta, m.k);
    }

    /// Roughness 0 without anisotropy: a smooth mirror (anisotropy makes alpha_t > 0).
    static bool smooth(const Material& m) { return m.roughness <= 0.0f && m.anisotropy <= 0.0f; }

    static BsdfLobe lobes(const Material& m) {
        return smooth(m) ? BsdfLobe::SpecularReflection : kRough;
    }

    /// wi is a reflection that both normals agree on.
    static bool reaches(const ShadingPoint& p, const glm::vec3& wo, const glm::vec3& wi) {
        return wo.z > 0.0f && wi.z > 0.0f && p.frame.above_geometry(wi);
    }

    [[gnu::noinline]] static BsdfSample sample(const Material& m, const ShadingPoint& p,
                                               const glm::vec3& wo, float uc, glm::vec2 u) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::sample_anisotropic<Conductor>(m, p, wo, uc, u);
        if (m.roughness <= 0.0f) {
            glm::vec3 wi(-wo.x, -wo.y, wo.z);
            if (!p.frame.above_geometry(wi)) wi = reflect(-wo, p.frame.geometric);
            const glm::vec3 f = microfacet::fresnel_conductor(std::fabs(wo.z), m.eta, m.k);
            return {wi, p.albedo * f, 1.0f, BsdfLobe::SpecularReflection};
        }
        if (wo.z <= 0.0f) return {};
        return sample_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo,
                           uc, u);
    }

    [[gnu::noinline]] static glm::vec3 eval(const Material& m, const ShadingPoint& p,
                                            const glm::vec3& wo, const glm::vec3& wi) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::eval_anisotropic<Conductor>(m, p, wo, wi);
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
            return microfacet::pdf_anisotropic<Conductor>(m, p, wo, wi);
        if (m.roughness <= 0.0f || !reaches(p, wo, wi)) return 0.0f;
        return pdf_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo, wi);
    }

    /// The rough sample for wo.z > 0, given the lobe (one lobe: uc is unused).
    template <class Ggx>
    static BsdfSample sample_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                                  const glm::vec3& wo, float /*uc*/, glm::vec2 u) {
        const glm::vec3 h = ggx.sample_visible_normal(wo, u);
        const glm::vec3 wi = reflect(-wo, h);
        if (!reaches(p, wo, wi)) return {};
        const float oh = glm::dot(wo, h);
        // f cos_i / pdf with pdf = vndf / (4 wo.h): F G2 / G1(wo).
        const glm::vec3 f = microfacet::fresnel_conductor(oh, m.eta, m.k);
        const float g = ggx.g2(wo, wi) / ggx.g1(wo);
        return {wi, p.albedo * f * g, pdf_with(ggx, m, p, wo, wi), kRough};
    }

    /// eval() for a reflection that reaches, given the lobe.
    template <class Ggx>
    static glm::vec3 eval_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                               const glm::vec3& wo, const glm::vec3& wi) {
        const glm::vec3 h = glm::normalize(wo + wi);
        // Torrance-Sparrow with GGX: F D G2 / (4 cos_o cos_i) (Walter et al. 2007, eq. 20).
        const float dg = ggx.d(h) * ggx.g2(wo, wi) / (4.0f * wo.z * wi.z);
        return p.albedo * microfacet::fresnel_conductor(glm::dot(wo, h), m.eta, m.k) * dg;
    }

    /// pdf() for a reflection that reaches, given the lobe.
    template <class Ggx>
    static float pdf_with(const Ggx& ggx, const Material& /*m*/, const ShadingPoint& /*p*/,
                          const glm::vec3& wo, const glm::vec3& wi) {
        return ggx.reflection_pdf(wo, glm::normalize(wo + wi));
    }
};

}  // namespace librt::bsdfs
