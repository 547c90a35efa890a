#pragma once

#include <cstdint>

namespace librt {

/// What kind of emitter a light is, as pbrt-v4's LightType: each light kind answers it
/// through its type() member, and the integrators and the scene ask it, never the kind.
enum class LightType : std::uint8_t {
    /// A point (point and spot lights): no ray can hit it; sample_li flags its sample delta
    /// and pdf_li is 0; sample_le's origin is a delta position.
    DeltaPosition,
    /// One direction from infinity (a sun without angular radius): no ray can hit it;
    /// sample_le's direction is a delta direction.
    DeltaDirection,
    /// A surface in the scene (sphere, triangle, quad, disk) that rays can hit, with a
    /// normal at each point (surface_normal).
    Area,
    /// Light from infinity over a solid angle (environment, sun with an angular radius):
    /// a ray leaving the scene sees it (escaped_radiance).
    Infinite,
};

/// True for the lights no ray can hit, whose sample_li directions are flagged is_delta.
[[nodiscard]] constexpr bool is_delta(LightType type) {
    return type == LightType::DeltaPosition || type == LightType::DeltaDirection;
}

/// True for the lights at infinity: those that take the scene's size in preprocess, have
/// no position to bound, and (Infinite) are seen by escaping rays.
[[nodiscard]] constexpr bool is_at_infinity(LightType type) {
    return type == LightType::DeltaDirection || type == LightType::Infinite;
}

}  // namespace librt
