#pragma once

// Private: a Ray copied one float at a time, for the hot queries that copy the ray they are
// given. Why: the rays the camera and the path loop build are stored field by field (a vec3
// as 8 + 4 bytes), and `Ray r = ray` compiles to 16-byte loads that span several of those
// stores. The store buffer cannot forward to such a load, so it waits until the stores reach
// the cache: a store-forwarding stall at every query that follows a freshly built ray (perf
// on the synthesis, docs/benchmarks.md "Where the last 7 % of CPU time goes"). A 4-byte load
// lies within one store whatever widths the producer used.

#include <librt/geometry/ray.h>
#include <librt/geometry/ray_offset.h>

#include <glm/vec3.hpp>

#include <limits>

namespace librt::detail {

/// One float loaded on its own, by one 4-byte load: written as the instruction itself, since
/// g++ otherwise merges neighbouring field loads into one wide load (the same value).
[[gnu::always_inline]] inline float load_alone(const float& f) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && defined(__SSE__)
    float v;
#if defined(__AVX__)
    asm("vmovss %1, %0" : "=x"(v) : "m"(f));
#else
    asm("movss %1, %0" : "=x"(v) : "m"(f));
#endif
    return v;
#else
    return f;
#endif
}

/// A copy of `ray` read by 4-byte loads (its stores are the compiler's choice).
[[nodiscard, gnu::always_inline]] inline Ray copy_by_floats(const Ray& ray) {
    Ray r;
    r.origin = {load_alone(ray.origin.x), load_alone(ray.origin.y), load_alone(ray.origin.z)};
    r.direction = {load_alone(ray.direction.x), load_alone(ray.direction.y),
                   load_alone(ray.direction.z)};
    r.t_min = load_alone(ray.t_min);
    r.t_max = load_alone(ray.t_max);
    return r;
}

/// Makes `ray` the ray leaving `point` (offset `offset`, Hit::offset) in `direction`, with
/// an unbounded extent, written in
/// place: assigned from a temporary, g++ stored the temporary field by field and copied it
/// by 16-byte loads that no store forwards to (a stall per bounce of the path loop).
/// `direction` may be `ray.direction` itself (a ray continuing through a surface).
[[gnu::always_inline]] inline void respawn(Ray& ray, const glm::vec3& point,
                                           const glm::vec3& normal, float offset,
                                           const glm::vec3& direction) {
    ray.origin = offset_ray_origin(point, normal, offset, direction);
    ray.direction = direction;
    ray.t_min = 0.0f;
    ray.t_max = std::numeric_limits<float>::infinity();
}

}  // namespace librt::detail
