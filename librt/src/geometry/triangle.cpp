#include <librt/geometry/triangle.h>

#include <cmath>

namespace librt {

std::optional<TriangleHit> intersect(const Triangle& tri, const Ray& ray) {
    const glm::vec3& dir = ray.direction;
    // Permute axes so that z is the direction's largest component (keeps Sz finite).
    const glm::vec3 ad = glm::abs(dir);
    int kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    if (!(ad[kz] > 0.0f)) return std::nullopt;  // zero or NaN direction
    int kx = (kz + 1) % 3;
    int ky = (kx + 1) % 3;
    if (dir[kz] < 0.0f) std::swap(kx, ky);  // preserve winding
    // Shear that maps the ray onto +z.
    const float sx = dir[kx] / dir[kz];
    const float sy = dir[ky] / dir[kz];
    const float sz = 1.0f / dir[kz];

    const glm::vec3 a = tri.p0 - ray.origin;
    const glm::vec3 b = tri.p1 - ray.origin;
    const glm::vec3 c = tri.p2 - ray.origin;
    const float ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    const float bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    const float cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];

    // 2D edge functions; a shared edge gives the exact negated value in the neighbour.
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        // Exactly on an edge in float: decide in double so the sign is exact.
        u = static_cast<float>(double(cx) * by - double(cy) * bx);
        v = static_cast<float>(double(ax) * cy - double(ay) * cx);
        w = static_cast<float>(double(bx) * ay - double(by) * ax);
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f))
        return std::nullopt;
    const float det = u + v + w;
    if (det == 0.0f) return std::nullopt;  // degenerate or edge-on

    const float az = sz * a[kz], bz = sz * b[kz], cz = sz * c[kz];
    const float t_scaled = u * az + v * bz + w * cz;
    const float inv_det = 1.0f / det;
    const float t = t_scaled * inv_det;
    if (!(t > ray.t_min && t < ray.t_max)) return std::nullopt;
    // u weighs p0 (edge p1-p2), v weighs p1, w weighs p2.
    return TriangleHit{t, v * inv_det, w * inv_det};
}

}  // namespace librt
