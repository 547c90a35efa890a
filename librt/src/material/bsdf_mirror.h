#pragma once

// The perfect mirror (MaterialKind::Mirror): one specular reflection lobe, tinted by albedo.

#include "material/specular.h"

#include <librt/material/bsdf.h>

namespace librt::bsdfs {

struct Mirror {
    static constexpr MaterialKind kKind = MaterialKind::Mirror;
    static constexpr BsdfLobe kLobes = BsdfLobe::SpecularReflection;

    static bool transmits(const Material& /*m*/) { return false; }
    static bool near_specular(const Material& /*m*/, float /*limit*/) { return true; }
    static bool casts_caustics(const Material& /*m*/, float /*max_roughness*/) { return true; }
    static void multiply_color(Material& m, const glm::vec3& c) { m.albedo *= c; }
    /// Its tint, what it reflects at every angle (the AOV follows it to the next surface).
    static glm::vec3 denoising_albedo(const Material& /*m*/, const ShadingPoint& p) {
        return p.albedo;
    }

    static BsdfSample sample(const Material& /*m*/, const ShadingPoint& p, const glm::vec3& wo,
                             float /*uc*/, glm::vec2 /*u*/) {
        // Reflection about the local +z (the shading normal): (-x, -y, z).
        glm::vec3 wi(-wo.x, -wo.y, wo.z);
        // A shading normal bent too far reflects below the real surface: use the geometric one.
        if (!p.frame.above_geometry(wi)) wi = reflect(-wo, p.frame.geometric);
        return {wi, p.albedo, 1.0f, kLobes};
    }

    static glm::vec3 eval(const Material& /*m*/, const ShadingPoint& /*p*/, const glm::vec3& /*wo*/,
                          const glm::vec3& /*wi*/) {
        return glm::vec3(0.0f);  // a delta lobe has no value at a given direction
    }

    static float pdf(const Material& /*m*/, const ShadingPoint& /*p*/, const glm::vec3& /*wo*/,
                     const glm::vec3& /*wi*/) {
        return 0.0f;
    }
};

}  // namespace librt::bsdfs
