#pragma once

#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>
#include <librt/render/scene.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>

// Shadow rays, built one way (pbrt-v4's SpawnRayTo and Unoccluded): from a surface point,
// moved off its surface by the self-intersection offset, to a target point, stopping the
// same offset short of it so that the surface the target lies on does not hide it.

namespace librt {

/// The ray from surface point p (unit geometric normal n, either orientation) to target:
/// origin offset_ray_origin(p, n, target - p), unit direction, t_max the distance to the
/// target minus ray_offset_scale(target) (0 when they are closer than that).
[[nodiscard]] inline Ray spawn_ray_to(const glm::vec3& p, const glm::vec3& n,
                                      const glm::vec3& target) {
    Ray r;
    r.origin = offset_ray_origin(p, n, target - p);
    const glm::vec3 rest = target - r.origin;
    const float len = glm::length(rest);
    if (!(len > 0.0f)) {
        r.t_max = 0.0f;  // nothing in between: the default direction is never traced
        return r;
    }
    r.direction = rest / len;
    r.t_max = std::max(0.0f, len - ray_offset_scale(target));
    return r;
}

/// True when nothing lies between surface point p (geometric normal n) and target, the
/// object `ignored_object` (e.g. the sphere light being sampled) skipped.
[[nodiscard]] inline bool unoccluded(const Scene& scene, const glm::vec3& p, const glm::vec3& n,
                                     const glm::vec3& target,
                                     std::uint32_t ignored_object = kInvalidId) {
    const Ray r = spawn_ray_to(p, n, target);
    return !(r.t_max > 0.0f) || !scene.occluded(r, ignored_object);
}

}  // namespace librt
