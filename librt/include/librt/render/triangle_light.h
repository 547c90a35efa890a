#pragma once

#include <librt/export.h>
#include <librt/render/light_sample.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace librt {

/// One emitting triangle of a mesh (Scene::commit makes one for every triangle whose
/// material emits). It emits `radiance` uniformly from both sides, as an emissive
/// material does when a ray hits it. Sampled uniformly by area (not by spherical
/// triangle: area sampling is cheap and exact, and the power light sampler already
/// spends samples where the big triangles are); pdf per solid angle d^2 / (A |cos|).
struct TriangleLight {
    glm::vec3 p0{0.0f};        ///< first corner (Triangle's convention)
    glm::vec3 p1{0.0f};        ///< second corner
    glm::vec3 p2{0.0f};        ///< third corner
    glm::vec3 radiance{0.0f};  ///< emitted radiance L (W / (sr m^2)) per channel, both sides
};

/// A point drawn uniformly on the triangle, as a direction from ref with its solid-angle
/// density; invalid when ref lies in the triangle's plane or the triangle is degenerate.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const TriangleLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// The solid-angle density of sample_li at ref for unit direction wi; 0 if wi misses.
[[nodiscard]] LIBRT_API float pdf_li(const TriangleLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// Total emitted power per channel: L pi A, times 2 for the two sides.
[[nodiscard]] LIBRT_API glm::vec3 power(const TriangleLight& light);

}  // namespace librt
