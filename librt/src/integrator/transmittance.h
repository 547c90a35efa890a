#pragma once

#include "scene/shadow_ray.h"

#include <librt/geometry/ray.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>

#include <cstdint>

// Null lobes (bsdf.h) as both path tracers cross them: shadow rays through them (the path
// tracer's light samples, the bidirectional tracer's connections) and a path's decision at
// one. Private to the library.

namespace librt {

/// Null lobes a shadow ray may cross before it counts as blocked: a bound, so that rays
/// grazing a stack of panes still end.
inline constexpr int kMaxShadowCrossings = 64;

/// The fraction of light that arrives along shadow ray `ray` (from spawn_ray_to) through
/// the surfaces it crosses: 0 at the first surface without a Null lobe, else the product
/// of their pass_through() colours (object `ignored_object`, a light's own surface,
/// skipped). For scenes with such surfaces (Scene::has_pass_through_surfaces), in place of
/// unoccluded(): its first closest hit gives the same answer for a ray blocked by an
/// opaque surface (asking unoccluded() first repeated the query for every blocked ray);
/// the others need only unoccluded()'s one any-hit query.
[[nodiscard]] glm::vec3 transmittance(const Scene& scene, Ray ray,
                                      std::uint32_t ignored_object = kInvalidId);

/// What shadow ray `ray` lets through: transmittance() in a scene with Null lobes, else
/// unoccluded()'s one any-hit query as 1 or 0. (The path tracer's light sample writes this
/// out itself, so that a blocked ray leaves the loop at once.)
[[nodiscard]] inline glm::vec3 shadow_transmittance(const Scene& scene, const Ray& ray,
                                                    std::uint32_t ignored_object = kInvalidId) {
    if (scene.has_pass_through_surfaces()) return transmittance(scene, ray, ignored_object);
    return unoccluded(scene, ray, ignored_object) ? glm::vec3(1.0f) : glm::vec3(0.0f);
}

/// What the join `ray` of a light path's vertex to a point on the lens (spawn_ray_between)
/// lets through: shadow_transmittance(), except that it crosses what camera rays cross
/// (Scene::camera_passes, as the camera sees along the reversed join: one-sided backs),
/// so that a light path reaches the camera wherever a camera ray reaches it.
[[nodiscard]] glm::vec3 lens_transmittance(const Scene& scene, const Ray& ray);

/// Crossing decisions a path may take before it ends: a bound, so that a path grazing a
/// stack of panes still ends (it also covers the max_depth bounces between panes).
inline constexpr std::uint32_t kMaxCrossingDecisions = 4096;

/// What a path does at a surface with a Null lobe, and the factor its throughput takes.
struct Crossing {
    bool crossed = false;  ///< true: goes on along the same direction; false: scatters here
    glm::vec3 weight{1.0f};
};

/// The decision at `hit` (material m, reached along unit `direction`) with a Null lobe:
/// cross with probability p, the mean of its colour T, weighted T / p, else scatter off the
/// rest of the BSDF, weighted 1 / (1 - p). The number comes from sampler dimension
/// SampleDimensions::kPassThrough + `decision`: a crossing is no bounce, and must not
/// reuse a bounce's numbers. Out of line, and returning its weight: taking the throughput
/// by reference made the path loop keep that in memory (callgrind on the synthesis: +13
/// instructions per sample).
[[nodiscard]] Crossing cross_null(const Scene& scene, const Material& m, const Hit& hit,
                                  const glm::vec3& direction, Sampler& sampler,
                                  std::uint32_t decision);

}  // namespace librt
