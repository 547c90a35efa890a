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

}  // namespace librt
