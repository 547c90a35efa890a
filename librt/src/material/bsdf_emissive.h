#pragma once

// A light's own surface (MaterialKind::Emissive): it emits (Material::emission, honoured
// for every kind) and scatters nothing, so it has no lobe and no BSDF value anywhere.

#include <librt/material/bsdf.h>

namespace librt::bsdfs {

struct Emissive {
    static constexpr MaterialKind kKind = MaterialKind::Emissive;
    static constexpr BsdfLobe kLobes = BsdfLobe::None;

    /// Absorbs what it does not emit: no ray passes it.
    static bool transmits(const Material& /*m*/) { return false; }
    /// Nothing to guide, nothing to cast.
    static bool near_specular(const Material& /*m*/, float /*limit*/) { return false; }
    static bool casts_caustics(const Material& /*m*/, float /*max_roughness*/) { return false; }
    /// Albedo, and the base colour an unlit surface emits (Material::unlit).
    static void multiply_color(Material& m, const glm::vec3& c) {
        m.albedo *= c;
        m.base_color *= c;
    }
    /// Reflects nothing.
    static glm::vec3 denoising_albedo(const Material& /*m*/, const ShadingPoint& /*p*/) {
        return glm::vec3(0.0f);
    }

    static BsdfSample sample(const Material& /*m*/, const ShadingPoint& /*p*/,
                             const glm::vec3& /*wo*/, float /*uc*/, glm::vec2 /*u*/) {
        return {};
    }
    static glm::vec3 eval(const Material& /*m*/, const ShadingPoint& /*p*/, const glm::vec3& /*wo*/,
                          const glm::vec3& /*wi*/) {
        return glm::vec3(0.0f);
    }
    static float pdf(const Material& /*m*/, const ShadingPoint& /*p*/, const glm::vec3& /*wo*/,
                     const glm::vec3& /*wi*/) {
        return 0.0f;
    }
};

}  // namespace librt::bsdfs
