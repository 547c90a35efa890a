#pragma once

#include <librt/geometry/ray.h>
#include <librt/geometry/ray_offset.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>

// Shadow rays, built one way (pbrt-v4's SpawnRayTo and Unoccluded): from a surface point,
// moved off its surface by the self-intersection offset, toward a target point. Toward a
// point, the ray stops a relative kShadowEpsilon short of it so that the surface the target
// lies on does not hide it; toward a light sample, it ends where the sample says
// (LightLiSample::distance), because each light knows whether its own surface is skipped.

namespace librt {

/// Fraction of a shadow ray's length left out at its far end (pbrt's ShadowEpsilon).
inline constexpr float kShadowEpsilon = 1e-4f;

/// The shadow ray of a light sample (LightLiSample's wi, distance and end_slope) from
/// surface point p (unit geometric normal n, either orientation, offset `offset`:
/// Hit::offset): origin offset_ray_origin(p, n, offset, wi), t_max the sample's distance,
/// unshortened but for end_slope times the offset. A light whose surface the shadow ray skips
/// (spheres, quads, disks) gives the emitting point itself: a relative margin there would let the
/// light shine through any wall within it (a sphere light buried in smallpt's ceiling lit the room
/// 0.5 % too brightly). Triangle lights end short themselves, and through end_slope short of where
/// the origin's offset shifts the end. No square root. Forced inline: with
/// offset_ray_origin inline in it, g++ kept it out of line in the path loop (callgrind on
/// the synthesis: +34 M instructions).
[[nodiscard, gnu::always_inline]] inline Ray spawn_ray_to(const glm::vec3& p, const glm::vec3& n,
                                                          float offset, const glm::vec3& wi,
                                                          float distance, float end_slope) {
    Ray r;
    r.origin = offset_ray_origin(p, n, offset, wi);
    r.direction = wi;
    r.t_max = std::max(distance - offset * end_slope, 0.0f);
    return r;
}

/// The shadow segment from surface point a (unit geometric normal na, offset offset_a) to
/// surface point b (na, offset_b; a zero normal for a point that is on no surface, a lens
/// or a point light): both ends moved off their surfaces toward each other, as pbrt-v4's
/// SpawnRayTo between two interactions does, then the ray from one to the other stopping
/// kShadowEpsilon short; t_max 0 (an empty segment) when they coincide. Each end's offset
/// covers the rounding of a test against its own surface, which kShadowEpsilon alone does
/// not near a huge triangle (issue 41).
[[nodiscard]] inline Ray spawn_ray_between(const glm::vec3& a, const glm::vec3& na, float offset_a,
                                           const glm::vec3& b, const glm::vec3& nb,
                                           float offset_b) {
    Ray r;
    r.origin = offset_ray_origin(a, na, offset_a, b - a);
    const glm::vec3 end = offset_ray_origin(b, nb, offset_b, a - b);
    const glm::vec3 rest = end - r.origin;
    const float len = glm::length(rest);
    if (!(len > 0.0f)) {
        r.t_max = 0.0f;  // nothing in between
        return r;
    }
    r.direction = rest / len;
    r.t_max = len * (1.0f - kShadowEpsilon);
    return r;
}

/// The shadow ray from surface point p (unit geometric normal n) to point target, which
/// lies on no surface the ray could meet (a lens): spawn_ray_between with ray_offset_scale(p)
/// at p and nothing at the target.
[[nodiscard]] inline Ray spawn_ray_to(const glm::vec3& p, const glm::vec3& n,
                                      const glm::vec3& target) {
    return spawn_ray_between(p, n, ray_offset_scale(p), target, glm::vec3(0.0f), 0.0f);
}

}  // namespace librt
