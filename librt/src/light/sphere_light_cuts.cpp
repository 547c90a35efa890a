#include "light/sphere_light_cuts.h"

#include <librt/geometry/ray_offset.h>
#include <librt/light/scene_summary.h>
#include <librt/light/sphere_light.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace librt {
namespace {

// The fraction of the light's surface in its smaller part: (1 + h) / 2 inside, (1 - h) / 2
// outside (a zone of a sphere has area 2 pi r^2 times its height in n . a, Archimedes).
double smaller_fraction(const SphereCut& c) { return 0.5 * (1.0 - std::fabs(c.h)); }

}  // namespace

std::optional<SphereCut> sphere_cut(const glm::dvec3& light_center, double light_radius,
                                    const glm::dvec3& center, double radius2) {
    const glm::dvec3 v = light_center - center;
    const double d = glm::length(v);
    if (!(d > 0.0) || !(light_radius > 0.0)) return std::nullopt;
    SphereCut c;
    c.center = center;
    c.radius2 = radius2;
    c.radius = std::sqrt(radius2);
    c.axis = v / d;
    // Inside S iff n . a <= h (derivation at SphereCut).
    c.h = (radius2 - d * d - light_radius * light_radius) / (2.0 * light_radius * d);
    if (!(c.h > -1.0 && c.h < 1.0)) return std::nullopt;
    c.inside_angle = std::acos(-c.h);
    // A tangent from the axis's smallest component (Hughes & Moeller 1999): never parallel.
    const glm::dvec3 a = c.axis;
    const glm::dvec3 e = std::fabs(a.x) <= std::fabs(a.y) && std::fabs(a.x) <= std::fabs(a.z)
                             ? glm::dvec3(1, 0, 0)
                         : std::fabs(a.y) <= std::fabs(a.z) ? glm::dvec3(0, 1, 0)
                                                            : glm::dvec3(0, 0, 1);
    c.tangent = glm::normalize(glm::cross(e, a));
    c.bitangent = glm::cross(a, c.tangent);
    return c;
}

SphereLightCuts make_sphere_light_cuts(const SphereCut* cuts, int count) {
    SphereLightCuts out;
    std::vector<SphereCut> sorted(cuts, cuts + std::max(count, 0));
    // Most restrictive first; ties keep the input order (the scene's object order): stable.
    std::stable_sort(sorted.begin(), sorted.end(), [](const SphereCut& x, const SphereCut& y) {
        return smaller_fraction(x) < smaller_fraction(y);
    });
    out.count = std::min(int(sorted.size()), kMaxSphereCuts);
    for (int i = 0; i < out.count; ++i) out.cut[std::size_t(i)] = sorted[std::size_t(i)];
    // Two parts, caps about axes c1, c2 with angular radii t1, t2, share no point iff
    // angle(c1, c2) > t1 + t2 (triangle inequality on the sphere). A cut's inside part is
    // the cap about -a of radius acos(-h), its outside part the cap about +a of radius
    // pi minus that; the angle between the parts' axes is angle(a_i, a_j) for equal sides,
    // pi minus it otherwise. Touching parts count as sharing: rounding decides nothing.
    constexpr double kMargin = 1e-9;
    for (int i = 0; i < out.count; ++i)
        for (int j = 0; j < out.count; ++j) {
            if (i == j) continue;
            const SphereCut& ci = out.cut[std::size_t(i)];
            const SphereCut& cj = out.cut[std::size_t(j)];
            const double between = std::acos(std::clamp(glm::dot(ci.axis, cj.axis), -1.0, 1.0));
            for (int si = 0; si < 2; ++si)
                for (int sj = 0; sj < 2; ++sj) {
                    const double ti = si == 1 ? ci.inside_angle : kPiDouble - ci.inside_angle;
                    const double tj = sj == 1 ? cj.inside_angle : kPiDouble - cj.inside_angle;
                    const double axes = si == sj ? between : kPiDouble - between;
                    if (axes > ti + tj + kMargin)
                        out.disjoint[std::size_t(i)][std::size_t(si)] |=
                            std::uint16_t(1u << (2 * j + sj));
                }
        }
    return out;
}

double sphere_cut_band(const glm::vec3& p) { return 2.0 * double(ray_offset_scale(p)); }

VisibleCap visible_cap(const SphereLight& light, const glm::vec3& p) {
    VisibleCap best;
    if (light.cuts == nullptr) return best;
    const SphereLightCuts& cuts = *light.cuts;
    const glm::dvec3 dp(p);
    const glm::dvec3 cl(light.sphere.center);
    const double rl = double(light.sphere.radius);
    // Inside the light (or on it) every cut is moot: the cone sampling handles it.
    const glm::dvec3 to_light = dp - cl;
    if (!(glm::dot(to_light, to_light) > rl * rl)) return best;
    const double band = sphere_cut_band(p);
    // Per cut: -1 unknown, 0 outside, 1 inside; `bound` has bit 2 i + side per known cut.
    std::array<int, kMaxSphereCuts> side{};
    unsigned bound = 0;
    double best_width = 2.0 * (2.0 * kMaxCapFraction);  // above any allowed cap
    int chosen = -1;
    for (int i = 0; i < cuts.count; ++i) {
        const SphereCut& c = cuts.cut[std::size_t(i)];
        // |p - c_S| against r_S -+ band, squared: no square root per cut.
        const glm::dvec3 v = dp - c.center;
        const double dist2 = glm::dot(v, v);
        const double lo = std::max(0.0, c.radius - band), hi = c.radius + band;
        const int s = dist2 < lo * lo ? 1 : dist2 > hi * hi ? 0 : -1;
        side[std::size_t(i)] = s;
        if (s < 0) continue;
        bound |= 1u << (2 * i + s);
        // The cap's height in n . a: 1 + h inside, 1 - h outside.
        const double width = s == 1 ? 1.0 + c.h : 1.0 - c.h;
        if (width < best_width) {
            best_width = width;
            chosen = i;
        }
    }
    for (int i = 0; i < cuts.count; ++i) {
        const int s = side[std::size_t(i)];
        if (s >= 0 && (cuts.disjoint[std::size_t(i)][std::size_t(s)] & bound) != 0) {
            best.kind = CapKind::Hidden;
            return best;
        }
    }
    if (chosen < 0 || best_width > 2.0 * kMaxCapFraction) return best;
    const SphereCut& c = cuts.cut[std::size_t(chosen)];
    best.kind = CapKind::Cap;
    best.cut = &c;
    if (side[std::size_t(chosen)] == 1) {
        best.z0 = -1.0;
        best.z1 = c.h;
    } else {
        best.z0 = c.h;
        best.z1 = 1.0;
    }
    return best;
}

void SphereLight::preprocess(const SceneSummary& scene) {
    std::vector<SphereCut> found;
    const glm::dvec3 light_center(sphere.center);
    const double light_radius = sphere.radius;
    for (const DoubleSphere& s : scene.opaque_spheres)
        if (const std::optional<SphereCut> cut =
                sphere_cut(light_center, light_radius, s.center, s.radius2))
            found.push_back(*cut);
    cuts = found.empty() ? nullptr
                         : std::make_shared<const SphereLightCuts>(
                               make_sphere_light_cuts(found.data(), int(found.size())));
}

}  // namespace librt
