#pragma once

// Private: a cheap upper bound of what one light can give a shading point, for choosing
// lights by their likely contribution there rather than by power alone (the idea of
// pbrt-v4's LightBounds, Conty & Kulla 2018's light-tree importance). Each light kind
// summarises itself once (its bounds() member, reached through light_bounds(Light)) by a
// sphere around its emitting points, a cone of the directions it emits into, and its
// power; importance() then costs a dozen multiplications and one square root per light
// and shading point. The light tree (light_tree.h) bounds groups of lights the same way.

#include <librt/export.h>
#include <librt/light/light.h>
#include <librt/light/light_sampler.h>

#include <glm/vec3.hpp>

namespace librt {

/// What a light's emitting points and directions are contained in.
struct LightBounds {
    glm::vec3 centre{0.0f};  ///< centre of a sphere containing every emitting point
    float radius = 0.0f;     ///< its radius (0 for a point), padded against rounding
    float phi = 0.0f;        ///< the light's power, mean over channels (W)
    /// Emits toward directions within the cone below only (one-sided planar lights, spots);
    /// false: every direction.
    bool cone = false;
    glm::vec3 axis{0.0f, 0.0f, 1.0f};  ///< unit cone axis (the way light leaves)
    /// cos of the cone's half angle: 0 for a one-sided planar light (its front hemisphere),
    /// cos(outer angle) for a spot.
    float cos_cone = 0.0f;
    /// Weigh by the cosine bound at the emitter (planar lights: emission falls as cos);
    /// false: the cone is a hard edge only (spots).
    bool emitter_cosine = false;
    /// A light at infinity: no distance, `axis` is the direction toward it when `cone`
    /// (a sun, cos_cone = cos of its angular radius), else it lights from everywhere.
    bool infinite = false;
};

/// The bounds of `light` (computed once per light, by the light sampler): its kind's
/// bounds().
[[nodiscard]] LIBRT_API LightBounds light_bounds(const Light& light);

/// A weight proportional to an upper bound of the light's contribution at `at`:
/// phi * (receiver cosine bound) * (emitter cosine bound) / max(d^2, r^2) for a finite light
/// (d the distance to the bounds' centre), phi * (receiver cosine bound) at infinity.
/// Exactly 0 only when the light provably gives `at` nothing: wholly below a reflecting
/// surface's plane, the point behind a one-sided emitter or outside a spot's cone, or phi 0.
[[nodiscard]] LIBRT_API float importance(const LightBounds& bounds, const LightChoicePoint& at);

namespace detail {

/// The bounds of a light emitting `power` (W per channel) from within the sphere (centre,
/// radius) into every direction: the radius padded so that rounding in the light's own
/// sample_li can never put an emitting point outside it; phi the power's mean over
/// channels (0 when negative or not finite).
[[nodiscard]] LightBounds finite_light_bounds(const glm::vec3& centre, float radius,
                                              const glm::vec3& power);
/// The bounds of a light at infinity emitting `power`, from every direction.
[[nodiscard]] LightBounds infinite_light_bounds(const glm::vec3& power);
/// Narrows b to a planar emitter of normal `normal`: a one-sided one emits into its front
/// hemisphere only, with radiance times cos falling toward the plane; a two-sided one
/// everywhere (b unchanged).
void bound_planar(LightBounds& b, const glm::vec3& normal, bool one_sided);

}  // namespace detail

}  // namespace librt
