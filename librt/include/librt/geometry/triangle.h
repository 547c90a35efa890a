#pragma once

#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <optional>
#include <utility>

namespace librt {

/// A triangle by its three corners. Point(u, v) = (1 - u - v) p0 + u p1 + v p2.
struct Triangle {
    glm::vec3 p0{0.0f},  ///< corner at (u, v) = (0, 0)
        p1{0.0f},        ///< corner at (u, v) = (1, 0)
        p2{0.0f};        ///< corner at (u, v) = (0, 1)
};

/// A ray-triangle hit: distance and barycentric (u, v).
struct TriangleHit {
    float t;  ///< ray parameter, in (t_min, t_max)
    float u;  ///< barycentric weight of p1
    float v;  ///< barycentric weight of p2 (p0's is 1 - u - v)
};

/// Per-ray constants of the watertight test: the axis permutation that makes the
/// direction's largest component z, and the shear that maps the direction onto +z
/// (Woop, Benthin and Wald). A corner p is tested as q = p - origin; sheared, the ray
/// is the +z axis. Computed once per ray, reused for every triangle it meets.
struct WatertightRay {
    glm::vec3 origin{0.0f};  ///< the ray's origin; triangles are translated by -origin
    int kx = 0,          ///< first 2D axis (0, 1, 2 = x, y, z): kz + 1 mod 3; kz + 2 if d[kz] < 0
        ky = 1,          ///< second 2D axis, the other of kz + 1, kz + 2 (the swap keeps winding)
        kz = 2;          ///< axis of the direction's largest |component|, the one mapped onto +z
    float sx = 0.0f,     ///< shear d[kx] / d[kz]: a corner's 2D x = q[kx] - sx * q[kz]
        sy = 0.0f,       ///< shear d[ky] / d[kz]: a corner's 2D y = q[ky] - sy * q[kz]
        sz = 0.0f;       ///< 1 / d[kz]: t = sz * (barycentric blend of the corners' q[kz])
    bool valid = false;  ///< false for a zero or NaN direction, which hits nothing
};

/// Prepares a ray for the watertight triangle test.
[[nodiscard]] inline WatertightRay prepare_watertight(const Ray& ray) {
    WatertightRay w;
    w.origin = ray.origin;
    const glm::vec3& d = ray.direction;
    const glm::vec3 ad = glm::abs(d);
    w.kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    if (!(ad[w.kz] > 0.0f)) return w;
    w.kx = (w.kz + 1) % 3;
    w.ky = (w.kx + 1) % 3;
    if (d[w.kz] < 0.0f) std::swap(w.kx, w.ky);  // keep the winding
    w.sx = d[w.kx] / d[w.kz];
    w.sy = d[w.ky] / d[w.kz];
    w.sz = 1.0f / d[w.kz];
    w.valid = true;
    return w;
}

/// Watertight ray-triangle test (Woop, Benthin and Wald, JCGT 2013): both faces, no
/// epsilon, scale independent; a ray through an edge or vertex shared by two triangles
/// hits at least one of them. Returns the hit when t is in (t_min, t_max).
[[nodiscard]] inline std::optional<TriangleHit> intersect(const Triangle& tri,
                                                          const WatertightRay& w, float t_min,
                                                          float t_max) {
    if (!w.valid) return std::nullopt;
    const glm::vec3 a3 = tri.p0 - w.origin;
    const glm::vec3 b3 = tri.p1 - w.origin;
    const glm::vec3 c3 = tri.p2 - w.origin;
    // glm's operator[] branches on the index; glm::vec3 is three contiguous floats.
    const float* a = &a3.x;
    const float* b = &b3.x;
    const float* c = &c3.x;
    const float ax = a[w.kx] - w.sx * a[w.kz], ay = a[w.ky] - w.sy * a[w.kz];
    const float bx = b[w.kx] - w.sx * b[w.kz], by = b[w.ky] - w.sy * b[w.kz];
    const float cx = c[w.kx] - w.sx * c[w.kz], cy = c[w.ky] - w.sy * c[w.kz];

    // 2D edge functions; a shared edge gives exactly the negated value in its neighbour.
    float e0 = cx * by - cy * bx;  // weight of p0 (edge p1-p2)
    float e1 = ax * cy - ay * cx;  // weight of p1
    float e2 = bx * ay - by * ax;  // weight of p2
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
        // On an edge in float: recompute in double so the sign is exact.
        e0 = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
        e1 = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
        e2 = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f))
        return std::nullopt;
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return std::nullopt;  // degenerate, or the ray lies in its plane

    // Distance: barycentric interpolation of the sheared z coordinates.
    const float t_scaled = w.sz * (e0 * a[w.kz] + e1 * b[w.kz] + e2 * c[w.kz]);
    const float inv_det = 1.0f / det;
    const float t = t_scaled * inv_det;
    if (!(t > t_min && t < t_max)) return std::nullopt;
    return TriangleHit{t, e1 * inv_det, e2 * inv_det};
}

/// Watertight test for a single ray (prepares it first).
[[nodiscard]] inline std::optional<TriangleHit> intersect(const Triangle& tri, const Ray& ray) {
    return intersect(tri, prepare_watertight(ray), ray.t_min, ray.t_max);
}

/// Bounding box of a triangle.
[[nodiscard]] inline BBox bounds(const Triangle& t) {
    BBox b;
    b.extend(t.p0);
    b.extend(t.p1);
    b.extend(t.p2);
    return b;
}

/// Centroid (mean of the corners), what the BVH builders split on.
[[nodiscard]] inline glm::vec3 centroid(const Triangle& t) {
    const glm::vec3 c = (t.p0 + t.p1 + t.p2) / 3.0f;
    if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) return c;
    return t.p0 / 3.0f + t.p1 / 3.0f + t.p2 / 3.0f;  // the sum overflowed (corners near 3e38)
}

/// Unnormalised normal (p1 - p0) x (p2 - p0); its length is twice the area.
[[nodiscard]] inline glm::vec3 area_normal(const Triangle& t) {
    return glm::cross(t.p1 - t.p0, t.p2 - t.p0);
}

}  // namespace librt
