#pragma once

#include <librt/export.h>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace librt {

/// The smallest cosine between a normal-mapped shading normal and the geometric normal:
/// apply_normal_map leans a bent normal back to at least this, so the shading hemisphere
/// always keeps a part above the real surface (the path loop's BSDFs end a path whose
/// sampled direction goes below it, and a normal at or past the horizon would end all).
inline constexpr float kMinNormalMapCosine = 0.01f;

/// A shading normal bent by a tangent-space normal map (glTF 2.0, material.normalTexture):
/// m = (2 texel - 1) * (scale, scale, 1) in the frame (T, B, n), where T is `tangent`.xyz
/// made perpendicular to n (Gram-Schmidt) and B = tangent.w cross(n, T); the result is m
/// normalised, leaned toward `geometric` (unit, on n's side) until its cosine with it is
/// at least kMinNormalMapCosine. A texel whose x and y decode to 0 (a flat texel) returns
/// n itself, bit for bit; so does a tangent that is zero or parallel to n (no frame).
[[nodiscard]] LIBRT_API glm::vec3 apply_normal_map(const glm::vec3& texel, float scale,
                                                   const glm::vec3& n, const glm::vec4& tangent,
                                                   const glm::vec3& geometric);

/// The smallest cosine between the geometric normal and the mirror direction of the viewer
/// about an adapted shading normal (adapt_shading_normal).
inline constexpr float kMinMirrorCosine = 0.01f;

/// A shading normal `n` (unit) adapted to the viewer `wo` (unit, toward the viewer) at a
/// surface of geometric normal `g` (unit; n, g and wo on one side or not, as the hit gives
/// them): n itself when wo's mirror direction about n, r = 2 (wo.n) n - wo, leaves above
/// the real surface (r.g' >= kMinMirrorCosine, g' = g turned to wo's side); else the normal
/// about which wo's mirror direction is r pulled up to that cosine (in the plane of r and g),
/// i.e. the half vector of wo and it, returned on the side n was given. A normal map bent
/// away from the viewer then still reflects a smooth metal's light to somewhere instead
/// of below the surface (the black rims of normal-mapped metals), so nothing is lost:
/// the local shading normal adaptation of Keller et al. 2017, "The Iray Light Transport
/// Simulation and Rendering System" (arXiv:1705.01263, its appendix). The normal depends on wo:
/// a light path (bidirectional tracer) adapts it to its own direction.
[[nodiscard]] LIBRT_API glm::vec3 adapt_shading_normal(const glm::vec3& n, const glm::vec3& g,
                                                       const glm::vec3& wo);

}  // namespace librt
