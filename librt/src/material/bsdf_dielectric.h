#pragma once

// Smooth glass (MaterialKind::Dielectric): Snell refraction, total internal reflection,
// and, when the material asks for it, reflection chosen with Schlick's probability F.

#include "material/specular.h"

#include <librt/material/bsdf.h>

#include <glm/geometric.hpp>

#include <algorithm>

namespace librt::bsdfs {

struct Dielectric {
    static constexpr MaterialKind kKind = MaterialKind::Dielectric;
    static constexpr BsdfLobe kLobes =
        BsdfLobe::SpecularReflection | BsdfLobe::SpecularTransmission;

    static bool transmits(const Material& /*m*/) { return true; }
    static bool near_specular(const Material& /*m*/, float /*limit*/) { return true; }
    static bool casts_caustics(const Material& /*m*/, float /*max_roughness*/) { return true; }
    static void multiply_color(Material& m, const glm::vec3& c) { m.albedo *= c; }
    /// Its tint: reflection and refraction together lose nothing (the AOV follows it).
    static glm::vec3 denoising_albedo(const Material& /*m*/, const ShadingPoint& p) {
        return p.albedo;
    }

    struct Scattered {
        glm::vec3 wi;
        bool transmitted;
        float probability;  ///< of this choice: 1, F or 1 - F
    };

    /// Scatters d (toward the surface) about the unit normal n, which faces d's origin side.
    /// `entering`: that side is the outside (index 1), the other the glass (index ior).
    /// With `fresnel`, reflects when u < F (Schlick), else refracts; without, always refracts
    /// (the report's behaviour); total internal reflection reflects either way.
    static Scattered scatter(const glm::vec3& d, const glm::vec3& n, bool entering, float ior,
                             bool fresnel, float u) {
        const float n1 = entering ? 1.0f : ior;
        const float n2 = entering ? ior : 1.0f;
        const float eta = n1 / n2;
        const float cos_i = std::clamp(-glm::dot(d, n), 0.0f, 1.0f);
        const float cos_t = refracted_cos(cos_i, eta);
        if (cos_t < 0.0f) return {reflect(d, n), false, 1.0f};  // total internal reflection
        float p_refract = 1.0f;
        if (fresnel) {
            const float f = schlick_fresnel(n1 <= n2 ? cos_i : cos_t, n1, n2);
            // Chosen with probability F and weighted F: the path weight is unchanged.
            if (u < f) return {reflect(d, n), false, f};
            p_refract = 1.0f - f;
        }
        return {refract(d, n, eta, cos_i, cos_t), true, p_refract};
    }

    static BsdfSample sample(const Material& m, const ShadingPoint& p, const glm::vec3& wo,
                             float uc, glm::vec2 /*u*/) {
        const glm::vec3 d = -wo;
        const bool entering = p.frame.front;
        Scattered s = scatter(d, glm::vec3(0.0f, 0.0f, 1.0f), entering, m.ior, m.fresnel, uc);
        // The shading normal must agree with the geometry about which side the new direction
        // is on; if not, scatter about the geometric normal.
        if (s.transmitted == p.frame.above_geometry(s.wi))
            s = scatter(d, p.frame.geometric, entering, m.ior, m.fresnel, uc);
        return {s.wi, p.albedo, s.probability,
                s.transmitted ? BsdfLobe::SpecularTransmission : BsdfLobe::SpecularReflection};
    }

    static glm::vec3 eval(const Material& /*m*/, const ShadingPoint& /*p*/, const glm::vec3& /*wo*/,
                          const glm::vec3& /*wi*/) {
        return glm::vec3(0.0f);  // delta lobes only
    }

    static float pdf(const Material& /*m*/, const ShadingPoint& /*p*/, const glm::vec3& /*wo*/,
                     const glm::vec3& /*wi*/) {
        return 0.0f;
    }
};

}  // namespace librt::bsdfs
