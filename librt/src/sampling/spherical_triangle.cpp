#include "sampling/spherical_triangle.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace librt {
namespace {

// The sampling runs in double: Arvo's inversion divides differences of nearly equal
// terms for thin triangles, and the cost is small next to the shadow ray it feeds.
using dvec3 = glm::dvec3;

// The part of v perpendicular to unit w, normalised (0 when v is parallel to w).
dvec3 perpendicular(const dvec3& v, const dvec3& w) {
    const dvec3 p = v - glm::dot(v, w) * w;
    const double len = glm::length(p);
    return len > 0.0 ? p / len : dvec3(0.0);
}

}  // namespace

float spherical_triangle_solid_angle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    // Van Oosterom & Strackee 1983: tan(omega / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a).
    const dvec3 da(a), db(b), dc(c);
    const double triple = std::fabs(glm::dot(da, glm::cross(db, dc)));
    const double denom = 1.0 + glm::dot(da, db) + glm::dot(db, dc) + glm::dot(dc, da);
    return float(2.0 * std::atan2(triple, denom));
}

SphericalTriangleSample sample_spherical_triangle(const glm::vec3& a, const glm::vec3& b,
                                                  const glm::vec3& c, float solid_angle,
                                                  glm::vec2 u) {
    if (!(solid_angle > 0.0f)) return {};
    // Renormalised in double: 1 - cos(arc A-B) is ~omega for a small triangle, and a float
    // direction's length error (~1e-7) would otherwise shift it by 1e-3 relative there.
    const dvec3 A = glm::normalize(dvec3(a)), B = glm::normalize(dvec3(b)),
                C = glm::normalize(dvec3(c));
    // The interior angle alpha at A, between the great arcs A-B and A-C: the angle between
    // their tangents at A, as a cosine and sine (no inverse trigonometry needed).
    const dvec3 tb = perpendicular(B, A), tc = perpendicular(C, A);
    const double cos_alpha = std::clamp(glm::dot(tb, tc), -1.0, 1.0);
    const double sin_alpha = glm::length(glm::cross(tb, tc));
    // Arvo 1995, fig. 2: the sub-triangle A, B, C' of area u.x * omega has C' on arc A-C at
    // cos(arc A-C') = q. The area is the angle excess alpha + beta + gamma - pi (Girard),
    // taken from Van Oosterom & Strackee's solid angle, which is the same number computed
    // more accurately; sin and cos of (area' - alpha) by the angle-difference identities.
    const double sub = double(u.x) * double(solid_angle);
    const double sin_sub = std::sin(sub), cos_sub = std::cos(sub);
    const double s = sin_sub * cos_alpha - cos_sub * sin_alpha;  // sin(sub - alpha)
    const double t = cos_sub * cos_alpha + sin_sub * sin_alpha;  // cos(sub - alpha)
    const double cos_c = glm::dot(A, B);                         // cosine of the arc A-B
    const double uu = t - cos_alpha;
    const double vv = s + sin_alpha * cos_c;
    const double den = (vv * s + uu * t) * sin_alpha;
    double q = den != 0.0 ? ((vv * t - uu * s) * cos_alpha - vv) / den : 1.0;
    q = std::clamp(q, -1.0, 1.0);
    const dvec3 c_hat = q * A + std::sqrt(std::max(0.0, 1.0 - q * q)) * perpendicular(C, A);
    // Then a point on arc B-C' with cos(arc B-P) = z uniform in [cos(arc B-C'), 1]: the
    // slice of the sub-triangle at each position along the arc.
    const double z = 1.0 - double(u.y) * (1.0 - glm::dot(c_hat, B));
    const dvec3 p = z * B + std::sqrt(std::max(0.0, 1.0 - z * z)) * perpendicular(c_hat, B);
    const double len = glm::length(p);
    if (!(len > 0.0)) return {};
    return {glm::vec3(p / len), solid_angle};
}

}  // namespace librt
