#include "obj/obj_polygon.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace librt::detail {

namespace {

/// Twice the signed area of the 2D triangle (a, b, c): positive when counter-clockwise.
double orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}
}  // namespace

/// Ear clipping (Meisters' two-ears theorem: a simple polygon always has an ear to cut) in the
/// polygon's own plane, appending triangles with the polygon's winding. Corners that add no
/// area are dropped first: repeats of the previous corner and the tips of zero-width spikes
/// (the boundary running out and back along one line), so weakly simple polygons triangulate
/// too. A polygon that is not simple may run out of ears; the rest is then fanned, and if the
/// triangles' total area differs from the polygon's (they overlap) nothing is appended.
Polygon triangulate_polygon(const std::vector<glm::vec3>& positions,
                            const std::vector<std::uint32_t>& corners, PolygonScratch& scratch,
                            std::vector<glm::uvec3>& out) {
    const std::size_t n = corners.size();
    const glm::dvec3 p0(positions[corners[0]]);
    // Newell's normal: the sum of (p_i - p0) x (p_i+1 - p0) is twice the vector area.
    glm::dvec3 normal(0.0);
    double extent2 = 0.0;
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const glm::dvec3 a = glm::dvec3(positions[corners[i]]) - p0;
        const glm::dvec3 b = glm::dvec3(positions[corners[i + 1]]) - p0;
        normal += glm::cross(a, b);
        extent2 = std::max(extent2, glm::dot(a, a));
    }
    const double len = glm::length(normal);
    if (!(len > 1e-12 * extent2)) return Polygon::ZeroArea;  // zero (or NaN) area

    // A right-handed orthonormal frame (u, v, n): the polygon runs counter-clockwise in (u, v).
    const glm::dvec3 nz = normal / len;
    const glm::dvec3 helper = std::abs(nz.x) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, nz));
    const glm::dvec3 v = glm::cross(nz, u);
    auto& pts = scratch.points;
    auto& rem = scratch.remaining;
    pts.resize(n);
    rem.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 d = glm::dvec3(positions[corners[i]]) - p0;
        pts[i] = {glm::dot(d, u), glm::dot(d, v)};
        rem[i] = i;
    }

    // Drop corners that add no area (see above); each leaves the signed area unchanged,
    // since the triangle (previous, corner, next) it removes is flat.
    const double tiny = 1e-12 * extent2;
    for (bool changed = true; changed && rem.size() > 3;) {
        changed = false;
        for (std::size_t k = 0; k < rem.size() && rem.size() > 3;) {
            const std::size_t m = rem.size();
            const glm::dvec2 a = pts[rem[(k + m - 1) % m]], b = pts[rem[k]],
                             c = pts[rem[(k + 1) % m]];
            const glm::dvec2 ab = b - a, bc = c - b;
            const bool repeat = glm::dot(ab, ab) <= tiny;
            // Collinear (|ab x bc| tiny against |ab| |bc|) and turning back (ab . bc < 0).
            const bool spike =
                std::abs(orient2d(a, b, c)) <= 1e-12 * glm::length(ab) * glm::length(bc) &&
                glm::dot(ab, bc) < 0.0;
            if (repeat || spike) {
                rem.erase(rem.begin() + static_cast<std::ptrdiff_t>(k));
                changed = true;
            } else {
                ++k;
            }
        }
    }

    // Twice the polygon's signed area (shoelace), to check the triangulation against.
    double polygon_area2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2& p = pts[i];
        const glm::dvec2& q = pts[(i + 1) % n];
        polygon_area2 += p.x * q.y - p.y * q.x;
    }
    const std::size_t first = out.size();
    double triangles_area2 = 0.0;  // sum of |twice the area| of the triangles emitted
    auto emit = [&](std::size_t a, std::size_t b, std::size_t c) {
        triangles_area2 += std::abs(orient2d(pts[a], pts[b], pts[c]));
        out.emplace_back(corners[a], corners[b], corners[c]);
    };
    while (rem.size() > 3) {
        const std::size_t m = rem.size();
        bool clipped = false;
        for (std::size_t k = 0; k < m && !clipped; ++k) {
            const std::size_t a = rem[(k + m - 1) % m], b = rem[k], c = rem[(k + 1) % m];
            if (orient2d(pts[a], pts[b], pts[c]) <= 0.0) continue;  // reflex or flat corner
            // An ear: no other corner inside or on the triangle (copies of its corners aside).
            bool empty = true;
            for (const std::size_t j : rem) {
                const glm::dvec2& q = pts[j];
                if (q == pts[a] || q == pts[b] || q == pts[c]) continue;
                if (orient2d(pts[a], pts[b], q) >= 0.0 && orient2d(pts[b], pts[c], q) >= 0.0 &&
                    orient2d(pts[c], pts[a], q) >= 0.0) {
                    empty = false;
                    break;
                }
            }
            if (!empty) continue;
            emit(a, b, c);
            rem.erase(rem.begin() + static_cast<std::ptrdiff_t>(k));
            clipped = true;
        }
        if (!clipped) break;
    }
    for (std::size_t i = 1; i + 1 < rem.size(); ++i) emit(rem[0], rem[i], rem[i + 1]);
    // Overlapping triangles cover more than the polygon: refuse rather than double the area.
    if (std::abs(triangles_area2 - std::abs(polygon_area2)) > 1e-6 * std::abs(polygon_area2)) {
        out.resize(first);
        return Polygon::NotSimple;
    }
    return Polygon::Triangulated;
}

}  // namespace librt::detail
