#pragma once

#include <librt/export.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace librt {

struct LightBounds;   // src/light/light_bounds.h: the light sampler's
struct SceneSummary;  // scene_summary.h

/// A spot light: a point emitting intensity I (W/sr) along `direction`, falling off
/// smoothly between the inner and outer cone angles as glTF KHR_lights_punctual defines:
/// with s = 1 / max(0.001, cos(inner) - cos(outer)), the factor
/// clamp((cos(theta) - cos(outer)) s, 0, 1)^2. A delta light: no ray can hit it.
struct SpotLight {
    glm::vec3 position{0.0f};                ///< where the light is
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  ///< cone axis, the way light goes (need not be unit)
    glm::vec3 intensity{0.0f};               ///< on the axis, W/sr per channel
    float inner_angle = 0.0f;                ///< radians, full intensity inside
    float outer_angle = 0.7853982f;          ///< radians (glTF default pi/4), dark outside

    /// A point: LightType::DeltaPosition.
    [[nodiscard]] static constexpr LightType type() { return LightType::DeltaPosition; }
    /// 0: a point has no surface.
    [[nodiscard]] static glm::vec3 surface_normal(const glm::vec3& /*p*/) {
        return glm::vec3(0.0f);
    }
    /// A sphere of radius 0 at the position, the directions of the outer cone.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Nothing to learn of the scene.
    static void preprocess(const SceneSummary& /*scene*/) {}
};

/// Throws librt::Error naming the parameter and value for non-finite vectors, a zero
/// direction, negative intensity, or angles not in 0 <= inner < outer <= pi/2 (glTF's rule).
LIBRT_API void validate(const SpotLight& light);

/// The glTF angular attenuation at cos_theta from the axis (0 outside the outer cone).
[[nodiscard]] LIBRT_API float spot_falloff(const SpotLight& light, float cos_theta);

/// The direction toward the light with I falloff / d^2 and pdf 1 (a delta light).
[[nodiscard]] LIBRT_API LightLiSample sample_li(const SpotLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// 0: no sampled direction hits a point.
[[nodiscard]] inline float pdf_li(const SpotLight& /*light*/, const glm::vec3& /*ref*/,
                                  const glm::vec3& /*wi*/) {
    return 0.0f;
}
/// A ray leaving the light (for paths that start there): from its position, a direction
/// uniform in the outer cone (pdf_dir 1 / (2 pi (1 - cos outer)): the falloff is 0
/// outside it), radiance the intensity times spot_falloff there, a delta position (pdf_pos
/// 1). u_pos is unused. Invalid for a position that is not finite, a zero direction or an
/// empty cone.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const SpotLight& light, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray along unit `direction`: pos 1 (the delta position;
/// origin and normal are not looked at), dir the cone's 1 / (2 pi (1 - cos outer)) inside
/// the outer cone, 0 outside.
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const SpotLight& light, const glm::vec3& origin,
                                          const glm::vec3& normal, const glm::vec3& direction);
/// Total emitted power: 2 pi I ((1 - cos inner) + (cos inner - cos outer) / 3), the
/// falloff integrated over the sphere.
[[nodiscard]] LIBRT_API glm::vec3 power(const SpotLight& light);

}  // namespace librt
