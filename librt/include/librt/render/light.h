#pragma once

#include <librt/export.h>
#include <librt/geometry/sphere.h>
#include <librt/sampling/warp.h>

#include <glm/vec3.hpp>

namespace librt {

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
        return {position, power / (4.0f * k_pi)};
    }
    /// Grey version of from_power: the same power in every channel.
    [[nodiscard]] static PointLight from_power(const glm::vec3& position, float power) {
        return from_power(position, glm::vec3(power));
    }
};

/// A spherical area light (the report's later light): a sphere whose surface emits a
/// uniform radiance, equal in every outgoing direction. Scene::add_sphere_light also adds
/// the sphere as an emissive object, so camera and bounce rays can hit it.
struct SphereLight {
    Sphere sphere;             ///< the emitting surface
    glm::vec3 radiance{0.0f};  ///< emitted radiance L (W / (sr m^2)) per channel

    /// The uniform radiance with which a sphere of the given radius emits `power` in
    /// total: power = L * pi * (4 pi r^2), so L = power / (4 pi^2 r^2). Far away it then
    /// lights a surface like PointLight::from_power(center, power).
    [[nodiscard]] static glm::vec3 radiance_for_power(const glm::vec3& power, float radius) {
        return power / (4.0f * k_pi * k_pi * radius * radius);
    }
    /// Grey version of radiance_for_power: the same power in every channel.
    [[nodiscard]] static glm::vec3 radiance_for_power(float power, float radius) {
        return radiance_for_power(glm::vec3(power), radius);
    }
};

/// Throws librt::Error naming the parameter and value if position or intensity is not
/// finite or intensity is negative.
LIBRT_API void validate(const PointLight& light);

/// Throws librt::Error naming the parameter and value if the sphere is not finite, its
/// radius is not > 0, or the radiance is negative or not finite.
LIBRT_API void validate(const SphereLight& light);

}  // namespace librt
