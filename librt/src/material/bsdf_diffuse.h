#pragma once

// The Lambertian BSDF (MaterialKind::Diffuse): f = albedo / pi on wo's side of the surface.

#include <librt/material/bsdf.h>
#include <librt/sampling/warp.h>

namespace librt::bsdfs {

struct Diffuse {
    static constexpr MaterialKind kKind = MaterialKind::Diffuse;
    static constexpr BsdfLobe kLobes = BsdfLobe::DiffuseReflection;

    static bool transmits(const Material& /*m*/) { return false; }
    static bool near_specular(const Material& /*m*/, float /*limit*/) { return false; }
    static bool casts_caustics(const Material& /*m*/, float /*max_roughness*/) { return false; }
    static void multiply_color(Material& m, const glm::vec3& c) { m.albedo *= c; }
    /// Lambert's directional albedo: its reflectance.
    static glm::vec3 denoising_albedo(const Material& /*m*/, const ShadingPoint& p) {
        return p.albedo;
    }

    /// Reflects only where both the shading and the geometric normal say "above": a
    /// direction under the real surface would leak light through it.
    static bool reaches(const ShadingPoint& p, const glm::vec3& wi) {
        return wi.z > 0.0f && p.frame.above_geometry(wi);
    }

    static BsdfSample sample(const Material& /*m*/, const ShadingPoint& p, const glm::vec3& /*wo*/,
                             float /*uc*/, glm::vec2 u) {
        const glm::vec3 wi = sample_cosine_hemisphere(u);
        // Below the true surface (a bent shading normal): no sample, the path ends there.
        if (!p.frame.above_geometry(wi)) return {};
        // Cosine sampling: (albedo / pi) cos / (cos / pi) = albedo.
        return {wi, p.albedo, cosine_hemisphere_pdf(wi.z), kLobes};
    }

    static glm::vec3 eval(const Material& /*m*/, const ShadingPoint& p, const glm::vec3& /*wo*/,
                          const glm::vec3& wi) {
        // Lambert: f = albedo / pi.
        return reaches(p, wi) ? p.albedo * kInvPi : glm::vec3(0.0f);
    }

    static float pdf(const Material& /*m*/, const ShadingPoint& p, const glm::vec3& /*wo*/,
                     const glm::vec3& wi) {
        return reaches(p, wi) ? cosine_hemisphere_pdf(wi.z) : 0.0f;
    }

    /// Lambert depends on wi only through its cosines with the shading normal (cos_s, wi.z
    /// in the local frame) and the geometric normal (cos_g), both turned to wo's side: eval()
    /// and pdf() from those, so that the path loop weighs a light sample with world-space
    /// dot products and builds no local frame for it (light_eval in
    /// src/integrator/integrators.cpp takes eval_cos / pdf_cos from any kind that has them).
    static bool reaches_cos(float cos_s, float cos_g) { return cos_s > 0.0f && cos_g > 0.0f; }
    static glm::vec3 eval_cos(const ShadingPoint& p, float cos_s, float cos_g) {
        return reaches_cos(cos_s, cos_g) ? p.albedo * kInvPi : glm::vec3(0.0f);
    }
    static float pdf_cos(float cos_s, float cos_g) {
        return reaches_cos(cos_s, cos_g) ? cosine_hemisphere_pdf(cos_s) : 0.0f;
    }
};

}  // namespace librt::bsdfs
