#pragma once

#include <librt/export.h>
#include <librt/geometry/hit.h>
#include <librt/light/directional_light.h>
#include <librt/light/disk_light.h>
#include <librt/light/environment_light.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>
#include <librt/light/point_light.h>
#include <librt/light/quad_light.h>
#include <librt/light/scene_summary.h>
#include <librt/light/sphere_light.h>
#include <librt/light/spot_light.h>
#include <librt/light/triangle_light.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <variant>

// The light seam. A light kind is a plain struct in its own header (point_light.h,
// sphere_light.h) that answers for itself: members type() (LightType: delta position,
// delta direction, area, infinite), surface_normal(p), bounds() (for the light sampler)
// and preprocess(SceneSummary) (what it learns of the scene: lights at infinity its
// radius), and free functions sample_li(light, ref, u) -> LightLiSample, pdf_li(light,
// ref, wi) and power(light), and for paths that start at lights sample_le(light, u_pos,
// u_dir) and pdf_le(light, origin, normal, direction) (lights at infinity take the scene's
// SceneSphere after the light). A light at infinity that escaping rays see (environment,
// sun with an angular radius) also has escaped_radiance(light, dir). Adding one is that
// header, its .cpp, and its name in LightSource; light.cpp checks every kind has the
// members (LightKind), and the functions below reach each kind only through std::visit
// with no fallback, so a kind that lacks one fails to compile. Code outside light/ asks
// these functions, never the variant's alternatives (cmake/CheckLayering.cmake).

namespace librt {

/// Every kind of light, as a tagged union. Why not a virtual interface: lights are plain
/// values the Scene stores contiguously and copies freely (no per-light allocation or
/// pointer to own), std::visit dispatches with a jump table and no indirect call in the
/// path loop, and a new type is registered by naming it here, after which the compiler
/// checks that it has every function the seam needs.
using LightSource = std::variant<PointLight, SphereLight, TriangleLight, QuadLight, DiskLight,
                                 SpotLight, DirectionalLight, EnvironmentLight>;

/// A light of a Scene: its source and, when it is also geometry, the object that is its
/// surface (so a BSDF-sampled ray that hits the object can find the light, and a shadow
/// ray toward the light can skip its own surface).
struct Light {
    LightSource source;  ///< what emits
    /// The scene object a shadow ray toward it skips (its own surface), if any. Emissive
    /// triangles of a mesh leave it kInvalidId: the mesh's other triangles may occlude.
    std::uint32_t object = kInvalidId;
    /// Emits only toward the side its surface's geometric normal faces (one-sided quad and
    /// disk lights, whose triangles are wound to face front).
    bool one_sided = false;
    /// Seen by camera rays; when false, camera rays pass through its surface (or, for a
    /// light at infinity, see black) while it still lights the scene.
    bool camera_visible = true;
};

/// What kind of emitter the light is (its kind's type()).
[[nodiscard]] inline LightType light_type(const Light& light) {
    return std::visit([](const auto& source) { return source.type(); }, light.source);
}

/// True for lights at infinity (a sun, an environment): no position, the scene's radius
/// from preprocess; those of LightType::Infinite are seen by rays that leave the scene.
[[nodiscard]] inline bool is_infinite(const Light& light) {
    return is_at_infinity(light_type(light));
}

/// The unit normal of the light's surface at point p on it (an area light's; 0 for a
/// light of a delta position or at infinity): what a path vertex on the light needs.
[[nodiscard]] LIBRT_API glm::vec3 surface_normal(const Light& light, const glm::vec3& p);

/// Lets the light learn what it needs of its scene (Scene::commit calls it for every
/// light once the geometry is built): lights at infinity take its radius, sphere lights
/// find the opaque spheres that bury part of them.
LIBRT_API void preprocess(Light& light, const SceneSummary& scene);

/// The SphereLight the light is, or nullptr: for the path loop's fast path, which calls
/// the sphere light's inline sample_li directly (the report scenes' kind) rather than
/// through std::visit's dispatch.
[[nodiscard]] inline const SphereLight* as_sphere_light(const Light& light) {
    return std::get_if<SphereLight>(&light.source);
}

/// The radiance a ray escaping the scene along unit direction dir receives from the light
/// (0 for every light not at infinity).
[[nodiscard]] inline glm::vec3 escaped_radiance(const Light& light, const glm::vec3& dir) {
    return std::visit(
        [&](const auto& source) -> glm::vec3 {
            if constexpr (requires { escaped_radiance(source, dir); })
                return escaped_radiance(source, dir);
            else
                return glm::vec3(0.0f);
        },
        light.source);
}

/// One direction toward the light from ref, drawn from u in [0, 1)^2.
[[nodiscard]] inline LightLiSample sample_li(const Light& light, const glm::vec3& ref,
                                             glm::vec2 u) {
    // Inline: the path loop calls it once per shading point.
    return std::visit([&](const auto& source) { return sample_li(source, ref, u); }, light.source);
}
/// The solid-angle density with which sample_li picks unit direction wi from ref (0 for
/// delta lights and for directions that miss the light).
[[nodiscard]] LIBRT_API float pdf_li(const Light& light, const glm::vec3& ref, const glm::vec3& wi);
/// Total emitted power per channel (W): what the light sampler weighs lights by.
[[nodiscard]] LIBRT_API glm::vec3 power(const Light& light);

/// A ray leaving the light, for paths that start there (light tracing, bidirectional path
/// tracing): its origin from u_pos, its direction from u_dir, both in [0, 1)^2. `scene`
/// (Scene::bounding_sphere) places the rays of lights at infinity; other lights ignore it.
/// See each light's sample_le for its densities; invalid for a degenerate light.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const Light& light, const SceneSphere& scene,
                                                glm::vec2 u_pos, glm::vec2 u_dir);
/// The densities with which sample_le draws the ray from `origin` (on the light, with unit
/// surface normal `normal` there on the emitting side) along unit `direction`: what MIS
/// weights of light paths need for a ray found another way. pos is 1 for a delta position
/// and dir 1 for a delta direction, as in LightLeSample; dir is 0 for a direction the light
/// does not emit in (behind a one-sided surface, outside a spot's cone).
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const Light& light, const SceneSphere& scene,
                                          const glm::vec3& origin, const glm::vec3& normal,
                                          const glm::vec3& direction);

}  // namespace librt
