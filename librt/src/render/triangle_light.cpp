#include "planar_light.h"

#include <librt/render/triangle_light.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

namespace librt {

LightLiSample sample_li(const TriangleLight& light, const glm::vec3& ref, glm::vec2 u) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f)) return {};
    const glm::vec2 b = sample_uniform_triangle(u);
    const glm::vec3 p = light.p0 + b.x * e1 + b.y * e2;
    return planar::toward(ref, p, c / len, 0.5f * len, light.radiance, true);
}

float pdf_li(const TriangleLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f)) return 0.0f;
    const glm::vec3 n = c / len;
    const planar::PlaneHit h = planar::hit_plane(light.p0, n, ref, wi, true);
    if (!(h.t > 0.0f)) return 0.0f;
    // Barycentrics of the plane point (sub-triangle areas over the whole, signed along n).
    const glm::vec3 q = h.point - light.p0;
    const float u = glm::dot(glm::cross(q, e2), n) / len;
    const float v = glm::dot(glm::cross(e1, q), n) / len;
    if (u < 0.0f || v < 0.0f || u + v > 1.0f) return 0.0f;
    return planar::pdf_of(h, 0.5f * len);
}

glm::vec3 power(const TriangleLight& light) {
    // Lambertian emitter: L pi per unit area and side (pbrt 4th ed. 12.5), both sides.
    const float area = 0.5f * glm::length(glm::cross(light.p1 - light.p0, light.p2 - light.p0));
    return light.radiance * (2.0f * k_pi * area);
}

}  // namespace librt
