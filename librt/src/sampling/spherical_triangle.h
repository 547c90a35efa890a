#pragma once

#include <librt/export.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace librt {

/// A direction drawn uniformly over the solid angle a triangle subtends.
struct SphericalTriangleSample {
    glm::vec3 direction{0.0f};  ///< unit direction inside the spherical triangle
    float solid_angle = 0.0f;   ///< the triangle's solid angle (sr); the density is its inverse
};

/// The solid angle (sr) of the spherical triangle with unit corner directions a, b, c,
/// by Van Oosterom and Strackee's formula (IEEE Trans. Biomed. Eng. 30(2), 1983):
/// tan(omega / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a). Accurate for tiny triangles,
/// where the angle-sum formula loses every digit.
[[nodiscard]] LIBRT_API float spherical_triangle_solid_angle(const glm::vec3& a, const glm::vec3& b,
                                                             const glm::vec3& c);

/// A direction uniformly distributed over the spherical triangle of unit corner directions
/// a, b, c (Arvo 1995, "Stratified Sampling of Spherical Triangles", SIGGRAPH): u.x picks
/// the sub-triangle of area u.x * omega (which fixes its third corner on the arc a-c), u.y
/// the point on the arc from b to that corner. Both maps are continuous, so strata of u
/// stay compact on the sphere. solid_angle must be spherical_triangle_solid_angle(a, b, c)
/// (callers have it already, to choose this sampler); no direction when it is 0.
[[nodiscard]] LIBRT_API SphericalTriangleSample sample_spherical_triangle(
    const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float solid_angle, glm::vec2 u);

}  // namespace librt
