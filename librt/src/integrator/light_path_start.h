#pragma once

// The first ray of a path that starts at a light, shared by the bidirectional tracer's
// light subpath and the path tracer's caustic light paths: a light of finite extent chosen
// by the scene's light sampler (by power, the pmf next-event estimation uses) and a ray
// drawn by its sample_le.

#include "integrator/mis.h"
#include "scene/shadow_ray.h"

#include <librt/geometry/ray_offset.h>
#include <librt/light/light.h>
#include <librt/light/light_sample.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace librt {

/// A light's ray, or none (valid() false).
struct LightPathStart {
    SampledLight chosen{};
    LightLeSample le{};
    bool valid = false;

    /// |cos| between the ray and the surface it leaves; 1 for a point-like light.
    [[nodiscard]] float cosine() const {
        return glm::dot(le.normal, le.normal) > 0.0f ? std::fabs(glm::dot(le.normal, le.direction))
                                                     : 1.0f;
    }
    /// How far rays leave the origin off the emitting surface (as Hit::offset for a hit).
    [[nodiscard]] float offset() const { return std::max(le.offset, ray_offset_scale(le.origin)); }
    /// The ray, its origin lifted off the emitting surface.
    [[nodiscard]] Ray ray() const {
        Ray r;
        r.origin = glm::dot(le.normal, le.normal) > 0.0f
                       ? offset_ray_origin(le.origin, le.normal, offset(), le.direction)
                       : le.origin;
        r.direction = le.direction;
        return r;
    }
};

/// Draws the light choice (1D at `first_dimension`), the origin (2D at + 1) and the
/// direction (2D at + 3). None when the sampler picks no light or one at infinity (which
/// starts no path), or sample_le gives nothing.
[[nodiscard]] inline LightPathStart start_light_path(const Scene& scene, const SceneSphere& sphere,
                                                     Sampler& sampler,
                                                     std::uint32_t first_dimension) {
    sampler.set_dimension(first_dimension);
    const float u_choice = sampler.next_1d();
    sampler.set_dimension(first_dimension + 1);
    const glm::vec2 u_pos = sampler.next_2d();
    sampler.set_dimension(first_dimension + 3);
    const glm::vec2 u_dir = sampler.next_2d();
    LightPathStart start;
    start.chosen = scene.light_sampler().sample(u_choice);
    if (!start.chosen.valid() || is_infinite(scene.lights()[start.chosen.light])) return start;
    start.le = sample_le(scene.lights()[start.chosen.light], sphere, u_pos, u_dir);
    start.valid = start.le.valid() && max_component(start.le.radiance) > 0.0f;
    return start;
}

}  // namespace librt
