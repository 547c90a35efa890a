#pragma once

#include <librt/geometry/ray.h>
#include <librt/geometry/ray_offset.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

// Shadow rays, built one way (pbrt-v4's SpawnRayTo and Unoccluded): from a surface point,
// moved off its surface by the self-intersection offset, toward a target point. Toward a
// point, the ray stops a relative kShadowEpsilon short of it so that the surface the target
// lies on does not hide it; toward a light sample, it ends where the sample says
// (LightLiSample::distance), because each light knows whether its own surface is skipped.

namespace librt {

/// Fraction of a shadow ray's length left out at its far end (pbrt's ShadowEpsilon).
inline constexpr float kShadowEpsilon = 1e-4f;

/// The shadow ray of a light sample from surface point p (unit geometric normal n, either
/// orientation) along unit direction wi: origin offset_ray_origin(p, n, wi), t_max =
/// `distance`, the sample's LightLiSample::distance, unshortened. A light whose surface the
/// shadow ray skips (spheres, quads, disks) gives the emitting point itself: a relative
/// margin there would let the light shine through any wall within it (a sphere light
/// buried in smallpt's ceiling lit the room 0.5 % too brightly). Triangle lights end
/// short themselves. No square root. Forced inline: with offset_ray_origin inline in it,
/// g++ kept it out of line in the path loop (callgrind on the synthesis: +34 M
/// instructions).
[[nodiscard, gnu::always_inline]] inline Ray spawn_ray_to(const glm::vec3& p, const glm::vec3& n,
                                                          const glm::vec3& wi, float distance) {
    Ray r;
    r.origin = offset_ray_origin(p, n, wi);
    r.direction = wi;
    r.t_max = distance;
    return r;
}

/// The shadow ray from surface point p (unit geometric normal n) to point target: unit
/// direction from the offset origin to target, t_max that distance (1 - kShadowEpsilon);
/// t_max 0 (an empty segment) when the two coincide.
[[nodiscard]] inline Ray spawn_ray_to(const glm::vec3& p, const glm::vec3& n,
                                      const glm::vec3& target) {
    Ray r;
    r.origin = offset_ray_origin(p, n, target - p);
    const glm::vec3 rest = target - r.origin;
    const float len = glm::length(rest);
    if (!(len > 0.0f)) {
        r.t_max = 0.0f;  // nothing in between
        return r;
    }
    r.direction = rest / len;
    r.t_max = len * (1.0f - kShadowEpsilon);
    return r;
}

}  // namespace librt
