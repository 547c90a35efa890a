#pragma once

#include <librt/geometry/ray.h>

#include <glm/vec3.hpp>

#include <cstdint>

// The arbitrary output variables (AOVs) of one camera sample, for denoisers and
// compositors. Private to the renderer; one function so that it can move onto the
// BSDF seam (lobe flags instead of Material::is_specular) in one place.

namespace librt {

class Scene;

/// What one camera sample contributes to the AOV layers.
struct AovSample {
    /// What the first non-specular hit's BSDF reflects or transmits (bsdf.h,
    /// denoising_albedo: textures applied), tinted by the mirrors and glass before it.
    glm::vec3 albedo{0.0f};
    glm::vec3 normal{0.0f};  ///< unit world-space shading normal at that hit (normal map
                             ///< applied; 0 when there is none)
    /// Planar depth of the first hit: its distance from the camera's lens plane along the
    /// optical axis (not the distance along the ray; valid when `hit`).
    float depth = 0.0f;
    bool hit = false;  ///< the camera ray hit something
    /// Radiance the camera ray's first hit emits toward the camera (0 from the back of a
    /// one-sided light), as the path tracer counts it there (fully: no MIS at the camera).
    glm::vec3 emission{0.0f};
};

/// Most mirror and glass surfaces followed before the albedo gives up (and is 0).
inline constexpr int kAovMaxSpecularBounces = 16;

/// The AOVs of the camera ray `ray` of sample `sample` of pixel (x, y), for a camera
/// whose unit optical axis is `forward` (Camera::forward; the ray starts on its lens
/// plane). Follows the ray through mirrors (reflection) and dielectrics (Fresnel-chosen
/// reflection or refraction, as the integrators choose) to the first non-specular hit,
/// whose material is shaded as the integrators shade it (Scene::shade: textures, vertex
/// colours, normal map, one-sided backs). Its random numbers come from their own stream
/// (seeded from the same pixel, sample and seed, but never from the integrator's sampler),
/// so computing AOVs leaves the beauty image unchanged.
[[nodiscard]] AovSample sample_aovs(const Scene& scene, const Ray& ray, const glm::vec3& forward,
                                    std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                                    std::uint64_t seed);

}  // namespace librt
