#pragma once

#include <librt/export.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>
#include <librt/sampling/warp.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace librt {

struct LightBounds;   // src/light/light_bounds.h: the light sampler's
struct SceneSummary;  // scene_summary.h

/// An isotropic point light (the report's first light). Not part of the geometry: no ray
/// can hit it, only shadow rays aimed at it see it.
struct PointLight {
    glm::vec3 position{0.0f};  ///< where the light is
    /// Radiant intensity I in W/sr per channel: a surface at distance d whose normal makes
    /// angle theta with the light receives irradiance E = I cos(theta) / d^2.
    glm::vec3 intensity{0.0f};

    /// The light of total power `power` (W, per channel) emitted uniformly over the
    /// sphere of directions: I = power / (4 pi). The report's formula
    /// I / (4 pi d^2) uses its I = 2.14e8 as such a power.
    [[nodiscard]] static PointLight from_power(const glm::vec3& position, const glm::vec3& power) {
        return {position, power / (4.0f * kPi)};
    }
    /// Grey version of from_power: the same power in every channel.
    [[nodiscard]] static PointLight from_power(const glm::vec3& position, float power) {
        return from_power(position, glm::vec3(power));
    }

    /// A point: LightType::DeltaPosition.
    [[nodiscard]] static constexpr LightType type() { return LightType::DeltaPosition; }
    /// 0: a point has no surface.
    [[nodiscard]] static glm::vec3 surface_normal(const glm::vec3& /*p*/) {
        return glm::vec3(0.0f);
    }
    /// A sphere of radius 0 at the position, every direction.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Nothing to learn of the scene.
    static void preprocess(const SceneSummary& /*scene*/) {}
};

/// Throws librt::Error naming the parameter and value if position or intensity is not
/// finite or intensity is negative.
LIBRT_API void validate(const PointLight& light);

/// The direction toward the light from ref, with radiance I / d^2 and pdf 1 (a delta
/// light); invalid when ref is at the light.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const PointLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// 0: no sampled direction hits a point.
[[nodiscard]] inline float pdf_li(const PointLight& /*light*/, const glm::vec3& /*ref*/,
                                  const glm::vec3& /*wi*/) {
    return 0.0f;
}
/// A ray leaving the light (for paths that start there): from its position, a direction
/// uniform over the sphere (pdf_dir 1 / (4 pi), as the light is isotropic), radiance the
/// intensity I, a delta position (pdf_pos 1). u_pos is unused. Invalid for a position that
/// is not finite.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const PointLight& light, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray along unit `direction`: pos 1 (the delta position;
/// origin and normal are not looked at), dir 1 / (4 pi).
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const PointLight& light, const glm::vec3& origin,
                                          const glm::vec3& normal, const glm::vec3& direction);
/// Total emitted power per channel: 4 pi I.
[[nodiscard]] inline glm::vec3 power(const PointLight& light) {
    return 4.0f * kPi * light.intensity;
}

}  // namespace librt
