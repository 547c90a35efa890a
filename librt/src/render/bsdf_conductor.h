#pragma once

// The rough conductor (MaterialKind::Conductor): GGX microfacet reflection with Smith
// height-correlated masking-shadowing and the exact conductor Fresnel of a complex index
// (eta + i k per channel), f = F(wo.h) D(h) G2(wo, wi) / (4 cos_o cos_i) (Walter et al.
// 2007, eq. 20), sampled by visible normals (Heitz 2018). Roughness 0 is a smooth mirror
// with the same Fresnel. Material::albedo is a tint over everything (1 by default).

#include "microfacet.h"

#include <librt/render/bsdf.h>
#include <librt/render/specular.h>

namespace librt::bsdfs {

struct Conductor {
    static constexpr BsdfLobe kLobes = BsdfLobe::Glossy | BsdfLobe::Reflection;

    static bool smooth(const Material& m) { return m.roughness <= 0.0f; }

    static BsdfLobe lobes(const Material& m) {
        return smooth(m) ? BsdfLobe::SpecularReflection : kLobes;
    }

    /// wi is a reflection that both normals agree on.
    static bool reaches(const ShadingPoint& p, const glm::vec3& wo, const glm::vec3& wi) {
        return wo.z > 0.0f && wi.z > 0.0f && p.frame.above_geometry(wi);
    }

    static BsdfSample sample(const Material& m, const ShadingPoint& p, const glm::vec3& wo,
                             float /*uc*/, glm::vec2 u) {
        if (smooth(m)) {
            glm::vec3 wi(-wo.x, -wo.y, wo.z);
            if (!p.frame.above_geometry(wi)) wi = reflect(-wo, p.frame.geometric);
            const glm::vec3 f = microfacet::fresnel_conductor(std::fabs(wo.z), m.eta, m.k);
            return {wi, p.albedo * f, 1.0f, BsdfLobe::SpecularReflection};
        }
        if (wo.z <= 0.0f) return {};
        const float alpha = microfacet::alpha_of(m.roughness);
        const glm::vec3 h = microfacet::sample_visible_normal(wo, alpha, u);
        const glm::vec3 wi = reflect(-wo, h);
        if (!reaches(p, wo, wi)) return {};
        const float oh = glm::dot(wo, h);
        // f cos_i / pdf with pdf = vndf / (4 wo.h): F G2 / G1(wo).
        const glm::vec3 f = microfacet::fresnel_conductor(oh, m.eta, m.k);
        const float g = microfacet::ggx_g2(wo, wi, alpha) / microfacet::ggx_g1(wo, alpha);
        return {wi, p.albedo * f * g, pdf(m, p, wo, wi), kLobes};
    }

    static glm::vec3 eval(const Material& m, const ShadingPoint& p, const glm::vec3& wo,
                          const glm::vec3& wi) {
        if (smooth(m) || !reaches(p, wo, wi)) return glm::vec3(0.0f);
        const float alpha = microfacet::alpha_of(m.roughness);
        const glm::vec3 h = glm::normalize(wo + wi);
        // Torrance-Sparrow with GGX: F D G2 / (4 cos_o cos_i) (Walter et al. 2007, eq. 20).
        const float dg =
            microfacet::ggx_d(h, alpha) * microfacet::ggx_g2(wo, wi, alpha) / (4.0f * wo.z * wi.z);
        return p.albedo * microfacet::fresnel_conductor(glm::dot(wo, h), m.eta, m.k) * dg;
    }

    static float pdf(const Material& m, const ShadingPoint& p, const glm::vec3& wo,
                     const glm::vec3& wi) {
        if (smooth(m) || !reaches(p, wo, wi)) return 0.0f;
        const float alpha = microfacet::alpha_of(m.roughness);
        const glm::vec3 h = glm::normalize(wo + wi);
        return microfacet::reflection_pdf(wo, h, alpha);
    }
};

}  // namespace librt::bsdfs
