#pragma once

#include <librt/export.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace librt {

struct LightBounds;   // src/light/light_bounds.h: the light sampler's
struct SceneSummary;  // scene_summary.h

/// A directional (sun) light: light arriving from `to_light` with irradiance E (W/m^2) on
/// a surface facing it. With angular_radius 0 it is a delta light; with angular_radius
/// theta > 0 it is a disk of directions of uniform radiance L = E / (pi sin^2 theta)
/// (E = L pi sin^2 theta for a uniform cone), sampled uniformly in the cone, and a ray
/// that escapes the scene inside the cone sees it (soft sun shadows).
struct DirectionalLight {
    glm::vec3 to_light{0.0f, 1.0f, 0.0f};  ///< toward the sun (need not be unit)
    glm::vec3 irradiance{0.0f};            ///< W/m^2 on a surface facing the sun
    float angular_radius = 0.0f;           ///< radians; the real sun's is about 0.00465
    float scene_radius = 0.0f;             ///< set by preprocess, for power()

    /// LightType::DeltaDirection without angular radius, else Infinite (a disk of
    /// directions that escaping rays see).
    [[nodiscard]] LightType type() const {
        return angular_radius > 0.0f ? LightType::Infinite : LightType::DeltaDirection;
    }
    /// 0: a light at infinity has no surface in the scene (its rays start on a disk facing
    /// along them, LightLeSample::normal).
    [[nodiscard]] static glm::vec3 surface_normal(const glm::vec3& /*p*/) {
        return glm::vec3(0.0f);
    }
    /// At infinity, the cone of directions toward the sun.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Takes the scene's radius, which power() needs (the sun lights the scene's disk).
    LIBRT_API void preprocess(const SceneSummary& scene);
};

/// Throws librt::Error naming the parameter and value for a non-finite or zero direction,
/// negative irradiance, or an angular radius not in [0, pi/2).
LIBRT_API void validate(const DirectionalLight& light);

/// A direction toward the sun (the axis when delta, else uniform in the cone) at infinite
/// distance.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const DirectionalLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// 1 / (cone solid angle) inside the cone; 0 outside or for a delta sun.
[[nodiscard]] LIBRT_API float pdf_li(const DirectionalLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// What a ray escaping along unit direction dir sees of the sun: L inside the cone.
[[nodiscard]] LIBRT_API glm::vec3 escaped_radiance(const DirectionalLight& light,
                                                   const glm::vec3& dir);
/// A ray leaving the sun toward the scene (for paths that start there): a direction toward
/// the sun wi drawn as sample_li draws it (the axis, a delta direction with pdf_dir 1 and
/// radiance the irradiance E, when the angular radius is 0; else uniform in the cone, pdf
/// 1 / (2 pi (1 - cos r)), radiance L), the ray going -wi from a point uniform on the disk
/// of radius R perpendicular to wi at center + R wi (pdf_pos 1 / (pi R^2)). Invalid for a
/// degenerate scene sphere or direction.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const DirectionalLight& light,
                                                const SceneSphere& scene, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray along unit `direction`: pos 1 / (pi R^2) (origin
/// and normal are not looked at), dir 1 for the delta sun (taken to be along the axis) or
/// the cone's density inside the cone, 0 outside.
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const DirectionalLight& light, const SceneSphere& scene,
                                          const glm::vec3& origin, const glm::vec3& normal,
                                          const glm::vec3& direction);
/// Power falling on the scene's bounding disk: E pi R^2 (for the light sampler).
[[nodiscard]] LIBRT_API glm::vec3 power(const DirectionalLight& light);

}  // namespace librt
