#pragma once

#include <librt/geometry/ray.h>
#include <librt/render/scene.h>

#include <glm/vec3.hpp>

#include <cstdint>

// Shadow rays through Null lobes (bsdf.h): what the path tracer's light samples and the
// bidirectional tracer's connections share. Private to the library.

namespace librt {

/// Null lobes a shadow ray may cross before it counts as blocked: a bound, so that rays
/// grazing a stack of panes still end.
inline constexpr int kMaxShadowCrossings = 64;

/// The fraction of light that arrives along shadow ray `ray` (from spawn_ray_to) through
/// the surfaces it crosses: 0 at the first surface without a Null lobe, else the product
/// of their pass_through() colours (object `ignored_object`, a light's own surface,
/// skipped). For scenes with such surfaces (Scene::has_pass_through_surfaces); the others
/// need only unoccluded()'s one any-hit query.
[[nodiscard]] glm::vec3 transmittance(const Scene& scene, Ray ray,
                                      std::uint32_t ignored_object = kInvalidId);

}  // namespace librt
