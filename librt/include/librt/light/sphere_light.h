#pragma once

#include <librt/export.h>
#include <librt/geometry/sphere.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <limits>
#include <memory>

namespace librt {

struct LightBounds;      // src/light/light_bounds.h: the light sampler's
struct SceneSummary;     // scene_summary.h
struct SphereLightCuts;  // src/light/sphere_light_cuts.h

/// A spherical area light (the report's later light): a sphere whose surface emits a
/// uniform radiance, equal in every outgoing direction. Scene::add_sphere_light also adds
/// the sphere as an emissive object, so camera and bounce rays can hit it.
struct SphereLight {
    Sphere sphere;             ///< the emitting surface
    glm::vec3 radiance{0.0f};  ///< emitted radiance L (W / (sr m^2)) per channel
    /// The opaque spheres that bury part of the light (src/light/sphere_light_cuts.h), or
    /// none: preprocess fills it for the scene's copy of the light (any value given is
    /// replaced); sample_li and pdf_li then see only the part a point can see.
    std::shared_ptr<const SphereLightCuts> cuts{};

    /// A surface: LightType::Area.
    [[nodiscard]] static constexpr LightType type() { return LightType::Area; }
    /// The unit outward normal at p (a point on the sphere).
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& p) const {
        return glm::normalize(p - sphere.center);
    }
    /// The sphere itself, every direction.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Finds the scene's opaque spheres that bury part of it (cuts).
    LIBRT_API void preprocess(const SceneSummary& scene);

    /// The uniform radiance with which a sphere of the given radius emits `power` in
    /// total: power = L * pi * (4 pi r^2), so L = power / (4 pi^2 r^2). Far away it then
    /// lights a surface like PointLight::from_power(center, power).
    [[nodiscard]] static glm::vec3 radiance_for_power(const glm::vec3& power, float radius) {
        return power / (4.0f * kPi * kPi * radius * radius);
    }
    /// Grey version of radiance_for_power: the same power in every channel.
    [[nodiscard]] static glm::vec3 radiance_for_power(float power, float radius) {
        return radiance_for_power(glm::vec3(power), radius);
    }
};

/// Throws librt::Error naming the parameter and value if the sphere is not finite, its
/// radius is not > 0, or the radiance is negative or not finite.
LIBRT_API void validate(const SphereLight& light);

/// A direction toward the part of the sphere visible from ref, uniform in the cone it
/// subtends (sample_sphere_direction), with the distance to the sphere along it; the
/// light's cuts ignored.
[[nodiscard]] inline LightLiSample sample_li_cone(const SphereLight& light, const glm::vec3& ref,
                                                  glm::vec2 u) {
    const SphereDirectionSample s =
        sample_sphere_direction(light.sphere.center, light.sphere.radius, ref, u);
    if (!(s.pdf > 0.0f) || !(s.pdf < std::numeric_limits<float>::infinity())) return {};
    return {s.direction, light.radiance, s.pdf, s.distance, false};
}
/// sample_li of a light with cuts: by visible_cap(light, ref), nothing when Hidden, a
/// point uniform in area on the cap (converted to solid angle: pdf = d^2 / (A |cos|);
/// nothing when it faces away from ref) when Cap, sample_li_cone when Whole.
[[nodiscard]] LIBRT_API LightLiSample sample_li_cut(const SphereLight& light, const glm::vec3& ref,
                                                    glm::vec2 u);
/// A direction toward the part of the sphere ref may see: sample_li_cut when the light
/// has cuts, else sample_li_cone.
[[nodiscard]] inline LightLiSample sample_li(const SphereLight& light, const glm::vec3& ref,
                                             glm::vec2 u) {
    if (light.cuts != nullptr) [[unlikely]]
        return sample_li_cut(light, ref, u);
    return sample_li_cone(light, ref, u);
}
/// The solid-angle density of sample_li at ref for unit direction wi; 0 if wi misses (or,
/// with cuts, misses the cap ref's samples are drawn from).
[[nodiscard]] LIBRT_API float pdf_li(const SphereLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// A ray leaving the light (for paths that start there): a point uniform over the whole
/// sphere (pdf_pos 1 / (4 pi r^2)), a direction cosine-weighted about the outward normal
/// there (pdf_dir cos / pi), radiance L. The cuts are not looked at: they say which part
/// of the light a point sees, and every part emits (a buried one into the opaque sphere
/// around it, which points inside it see), as power() counts. Invalid for a radius that
/// is not finite and > 0.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const SphereLight& light, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray from `origin` on the sphere, where the outward unit
/// normal is `normal`, along unit `direction`: pos 1 / (4 pi r^2), dir cos / pi (0 into
/// the sphere).
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const SphereLight& light, const glm::vec3& origin,
                                          const glm::vec3& normal, const glm::vec3& direction);
/// Total emitted power per channel: L pi (4 pi r^2).
[[nodiscard]] LIBRT_API glm::vec3 power(const SphereLight& light);

}  // namespace librt
