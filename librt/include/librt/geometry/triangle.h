#pragma once

#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace librt {

/// A triangle by its three corners. Point(u, v) = (1 - u - v) p0 + u p1 + v p2.
struct Triangle {
    glm::vec3 p0{0.0f}, p1{0.0f}, p2{0.0f};
};

/// A ray-triangle hit: distance and barycentric (u, v).
struct TriangleHit {
    float t;
    float u;
    float v;
};

/// Watertight ray-triangle test (Woop, Benthin and Wald, JCGT 2013): both faces,
/// no epsilon, scale independent, and a ray through an edge or vertex shared by two
/// triangles hits at least one of them. Returns the hit when t is in (t_min, t_max).
[[nodiscard]] std::optional<TriangleHit> intersect(const Triangle& tri, const Ray& ray);

/// Bounding box of a triangle.
[[nodiscard]] inline BBox bounds(const Triangle& t) {
    BBox b;
    b.extend(t.p0);
    b.extend(t.p1);
    b.extend(t.p2);
    return b;
}

/// Centroid (mean of the corners), what the BVH builders split on.
[[nodiscard]] inline glm::vec3 centroid(const Triangle& t) { return (t.p0 + t.p1 + t.p2) / 3.0f; }

/// Unnormalised normal (p1 - p0) x (p2 - p0); its length is twice the area.
[[nodiscard]] inline glm::vec3 area_normal(const Triangle& t) {
    return glm::cross(t.p1 - t.p0, t.p2 - t.p0);
}

}  // namespace librt
