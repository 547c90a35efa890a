#pragma once

#include <glm/vec3.hpp>

namespace librt {

/// What a light's sample_li returns: one direction from a reference point toward the
/// light, with the radiance arriving along it and its density.
struct LightLiSample {
    glm::vec3 wi{0.0f};  ///< unit direction from the reference point toward the light
    /// Radiance arriving at the reference point along -wi. For a delta light (a point), the
    /// factor that times cos(theta) gives the irradiance: I / d^2.
    glm::vec3 radiance{0.0f};
    float pdf = 0.0f;  ///< per unit solid angle at the reference point; 1 for a delta light
    /// Where a shadow ray toward the sample ends (spawn_ray_to uses it as it is): the
    /// distance from the reference point to the emitting point along wi. Lights whose own
    /// surface the shadow ray skips give it exactly; triangle lights, which cannot skip
    /// theirs, shorten it by the ray offsets of both ends (see triangle_light.cpp).
    float distance = 0.0f;
    bool is_delta = false;  ///< a delta light: no BSDF-sampled direction can find it

    /// True when there is a direction to use (pdf > 0).
    [[nodiscard]] bool valid() const { return pdf > 0.0f; }
};

}  // namespace librt
