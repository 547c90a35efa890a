#pragma once

#include "geometry/spawn_ray.h"

#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>
#include <librt/scene/scene.h>

// Whether a shadow ray (geometry/spawn_ray.h) reaches its end through the scene.

namespace librt {

/// True when nothing blocks the shadow ray r (from spawn_ray_to), the object
/// `ignored_object` (e.g. the sphere light being sampled) skipped.
// Forced inline, as Scene::occluded: g++ made it a call in the path loop once the loop
// grew (callgrind on the synthesis: +16 M instructions).
[[nodiscard, gnu::always_inline]] inline bool unoccluded(
    const Scene& scene, const Ray& r, std::uint32_t ignored_object = kInvalidId) {
    return !(r.t_max > 0.0f) || !scene.occluded(r, ignored_object);
}

/// True when nothing lies between surface point p (geometric normal n) and target, the
/// object `ignored_object` skipped.
[[nodiscard]] inline bool unoccluded(const Scene& scene, const glm::vec3& p, const glm::vec3& n,
                                     const glm::vec3& target,
                                     std::uint32_t ignored_object = kInvalidId) {
    return unoccluded(scene, spawn_ray_to(p, n, target), ignored_object);
}

}  // namespace librt
