#include "geometry/spawn_ray.h"
#include "light/emission.h"
#include "light/light_bounds.h"
#include "light/planar_light.h"
#include "sampling/spherical_triangle.h"

#include <librt/geometry/ray_offset.h>
#include <librt/light/triangle_light.h>
#include <librt/sampling/warp.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

namespace librt {
namespace {

// The texture coordinate at barycentrics b, interpolated as a hit on the triangle
// interpolates it (the slot's affine transform commutes with the interpolation).
glm::vec2 uv_at(const TriangleLight& light, glm::vec2 b) {
    return (1.0f - b.x - b.y) * light.uv0 + b.x * light.uv1 + b.y * light.uv2;
}

bool positive(const glm::vec3& v) { return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f; }

// The most texels emits_nowhere reads to prove a triangle black: a triangle's share of a
// 2048^2 atlas is far below it; one spanning more is left to the mean's estimate.
constexpr std::size_t kMaxTexelsScanned = std::size_t{1} << 14;
// mean_texture_estimate's most strata a side (1024 lookups), beyond which it averages
// the texels themselves (up to 16 kMaxTexelsScanned of them: a 512^2 footprint).
constexpr float kMaxMeanStrata = 32.0f;

}  // namespace

glm::vec3 radiance_at(const TriangleLight& light, glm::vec2 b) {
    if (!light.texture) return light.radiance;
    return light.radiance * light.texture->lookup(uv_at(light, b));
}

glm::vec3 mean_texture_estimate(const TriangleLight& light) {
    if (!light.texture) return glm::vec3(1.0f);
    const ImageTexture& tex = *light.texture;
    // The texels the triangle covers: its uv area times the texture's size.
    const glm::vec2 d1 = light.uv1 - light.uv0, d2 = light.uv2 - light.uv0;
    const float cross = d1.x * d2.y - d1.y * d2.x;
    const float w = float(tex.width()), h = float(tex.height());
    const float texels = 0.5f * std::fabs(cross) * w * h;
    if (texels > kMaxMeanStrata * kMaxMeanStrata / 2 && std::isfinite(texels)) {
        // Many texels: the mean of the texels whose centres lie in the uv triangle. Each
        // texel's bilinear hat integrates to one texel's area, so that is the integral up to
        // the texels along the edges (a lamp of a few texels in thousands: exact).
        const glm::vec2 lo = glm::min(glm::min(light.uv0, light.uv1), light.uv2);
        const glm::vec2 hi = glm::max(glm::max(light.uv0, light.uv1), light.uv2);
        // Texel centres at u = (i + 0.5) / w and v = 1 - (j + 0.5) / h (rows run down),
        // i and j unwrapped (lookup wraps them).
        const float i0 = std::ceil(lo.x * w - 0.5f), i1 = std::floor(hi.x * w - 0.5f);
        const float j0 = std::ceil((1.0f - hi.y) * h - 0.5f),
                    j1 = std::floor((1.0f - lo.y) * h - 0.5f);
        if ((i1 - i0 + 1.0f) * (j1 - j0 + 1.0f) <= float(kMaxTexelsScanned) * 16.0f) {
            glm::vec3 sum(0.0f);
            std::size_t count = 0;
            for (float j = j0; j <= j1; j += 1.0f)
                for (float i = i0; i <= i1; i += 1.0f) {
                    const glm::vec2 q{(i + 0.5f) / w, 1.0f - (j + 0.5f) / h};
                    // Barycentrics of q in the uv triangle.
                    const glm::vec2 e = q - light.uv0;
                    const float b1 = (e.x * d2.y - e.y * d2.x) / cross;
                    const float b2 = (d1.x * e.y - d1.y * e.x) / cross;
                    if (b1 < 0.0f || b2 < 0.0f || b1 + b2 > 1.0f) continue;
                    sum += tex.lookup(q);
                    ++count;
                }
            if (count >= 64) return sum / float(count);
        }
    }
    // Few texels (or too many to visit): lookups at the centres of an n x n stratification
    // of the triangle, about two a texel (the bilinear texture varies within a texel only
    // linearly), n from 4 to kMaxMeanStrata. sample_uniform_triangle is area-preserving, so
    // the strata have equal areas.
    const float wanted = std::isfinite(texels) ? std::ceil(std::sqrt(2.0f * texels)) : 0.0f;
    const int n = int(std::clamp(wanted, 4.0f, kMaxMeanStrata));
    glm::vec3 sum(0.0f);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const glm::vec2 u{(float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n)};
            sum += tex.lookup(uv_at(light, sample_uniform_triangle(u)));
        }
    return sum / float(n * n);
}

bool emits_nowhere(const TriangleLight& light) {
    if (!positive(light.radiance)) return true;
    if (!light.texture) return false;
    // A hit's uv is a convex combination of the corners': within their box.
    const glm::vec2 lo = glm::min(glm::min(light.uv0, light.uv1), light.uv2);
    const glm::vec2 hi = glm::max(glm::max(light.uv0, light.uv1), light.uv2);
    const std::optional<glm::vec3> m = light.texture->max_over(lo, hi, kMaxTexelsScanned);
    return m && !positive(*m * light.radiance);
}

namespace {

// Which sampler a reference point gets (sample_li and pdf_li decide alike): spherical
// triangle sampling when the triangle looks big from ref, A / d_c^2 >= 0.1 (d_c the
// distance to its centroid; about its solid angle, cheap to get without trigonometry).
// Below that its points lie within ~10 degrees of each other as seen from ref, so d^2 / cos
// varies little over it and uniform area sampling is about as good and much cheaper: on
// light_targets' one-sided panel, spherical sampling everywhere took 1.7x the time per
// sample for the same variance. Above it, near the emitter, area sampling's weights
// d^2 / (A cos) explode and spherical sampling's stay below 2 pi L. (pbrt-v4 switches at
// a solid angle of 3e-4 sr; its threshold favours variance, this one time at equal error.)
constexpr float kMinSphericalSize = 0.1f;

bool spherical_sampling(const TriangleLight& light, const glm::vec3& ref, float area) {
    const glm::vec3 d = (light.p0 + light.p1 + light.p2) * (1.0f / 3.0f) - ref;
    return area >= kMinSphericalSize * glm::dot(d, d);
}

// The unit directions from ref to the corners and the solid angle they span, or a solid
// angle of 0 when ref is in the triangle's plane, behind a one-sided triangle, or the
// triangle is degenerate. n is its unit front normal.
struct Corners {
    glm::vec3 a{0.0f}, b{0.0f}, c{0.0f};
    float solid_angle = 0.0f;
};
Corners corners_from(const TriangleLight& light, const glm::vec3& ref, const glm::vec3& n) {
    const float side = glm::dot(ref - light.p0, n);  // > 0 in front
    if (!(side != 0.0f) || (!light.two_sided && !(side > 0.0f))) return {};
    const glm::vec3 a = light.p0 - ref, b = light.p1 - ref, c = light.p2 - ref;
    const float la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    if (!(la > 0.0f) || !(lb > 0.0f) || !(lc > 0.0f)) return {};
    Corners k{a / la, b / lb, c / lc, 0.0f};
    k.solid_angle = spherical_triangle_solid_angle(k.a, k.b, k.c);
    return k;
}

// Barycentrics (b1, b2) of a point q of the triangle's plane (sub-triangle areas over the
// whole, signed along n; len = |cross(e1, e2)|).
glm::vec2 barycentrics(const TriangleLight& light, const glm::vec3& q, const glm::vec3& n,
                       float len) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 d = q - light.p0;
    return {glm::dot(glm::cross(d, e2), n) / len, glm::dot(glm::cross(e1, d), n) / len};
}

// The rounding of a ray's test against the triangle near its plane: ray_offset_scale of its
// largest corner coordinates, which bound barycentric_offset at any of its points.
float corner_offset(const TriangleLight& light) {
    return ray_offset_scale(
        glm::max(glm::max(glm::abs(light.p0), glm::abs(light.p1)), glm::abs(light.p2)));
}

// How far the shadow ray toward the emitting point q (ray parameter t along wi from ref,
// dn = wi . n) may go without meeting the emitter's own plane. A triangle light's shadow
// ray cannot skip its object (the mesh may hold other triangles that do shade), so the
// segment ends short of the plane by the rounding of the test that would find the light:
// the light's barycentric_offset bound, which the largest vertex coordinates bound (q
// itself is found within that of the plane), over |dn|; then by the relative
// kShadowEpsilon, as every shadow ray did before spawn_ray_to left the margin to the
// light. The ray's origin offset, known only to the caller, is taken off by spawn_ray_to
// through end_slope (pbrt-v4 likewise offsets both ends of a shadow ray, SpawnRayTo).
// 0 (nothing can be in between) when the point is that close to the plane.
LightLiSample shadow_sample(const TriangleLight& light, glm::vec3 wi, glm::vec3 radiance, float pdf,
                            float t, float dn) {
    const float slope = 1.0f / std::fabs(dn);
    const float margin = corner_offset(light) * slope;
    LightLiSample s;
    s.wi = wi;
    s.radiance = radiance;
    s.pdf = pdf;
    s.distance = t > margin ? (t - margin) * (1.0f - kShadowEpsilon) : 0.0f;
    s.end_slope = slope;
    return s;
}

// True when ref lies in the triangle's plane up to the rounding of a surface point (the
// ray offset's scale): a point of the emitter itself, or of a coplanar triangle of its
// mesh. Nothing there can see the triangle but along the plane, yet a spherical triangle
// drawn from a point 10^-7 off its plane spans a hemisphere, with a shadow ray too short to
// meet anything: an emissive panel with a specular layer lit itself (PathTracer read a
// glTF panel 1 % too bright, brute force did not).
bool in_plane(const TriangleLight& light, const glm::vec3& ref, const glm::vec3& n) {
    return !(std::fabs(glm::dot(ref - light.p0, n)) > ray_offset_scale(ref));
}

}  // namespace

LightLiSample sample_li(const TriangleLight& light, const glm::vec3& ref, glm::vec2 u) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f)) return {};
    const glm::vec3 n = c / len;
    if (in_plane(light, ref, n)) return {};
    if (spherical_sampling(light, ref, 0.5f * len)) {
        const Corners k = corners_from(light, ref, n);
        const float omega = k.solid_angle;
        if (!(omega > 0.0f)) return {};
        // Uniform over the solid angle: the weight L cos / pdf = L cos omega stays below
        // 2 pi L however close ref is, where area sampling's d^2 / (A cos) explodes.
        const SphericalTriangleSample st = sample_spherical_triangle(k.a, k.b, k.c, omega, u);
        const float dn = glm::dot(st.direction, n);
        const float t = glm::dot(light.p0 - ref, n) / dn;
        if (!(st.solid_angle > 0.0f) || !(t > 0.0f) || !std::isfinite(t)) return {};
        const glm::vec3 q = ref + t * st.direction;
        LightLiSample s = shadow_sample(light, st.direction, light.radiance, 1.0f / omega, t, dn);
        if (light.texture) {
            const glm::vec2 b = glm::clamp(barycentrics(light, q, n, len), 0.0f, 1.0f);
            s.radiance = radiance_at(light, b);
        }
        return s;
    }
    const glm::vec2 b = sample_uniform_triangle(u);
    const glm::vec3 p = light.p0 + b.x * e1 + b.y * e2;
    LightLiSample s = planar::toward(ref, p, n, 0.5f * len, light.radiance, light.two_sided);
    if (!s.valid()) return s;
    s = shadow_sample(light, s.wi, s.radiance, s.pdf, s.distance, glm::dot(s.wi, n));
    if (light.texture) s.radiance = radiance_at(light, b);
    return s;
}

float pdf_li(const TriangleLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f)) return 0.0f;
    const glm::vec3 n = c / len;
    if (in_plane(light, ref, n)) return 0.0f;
    const planar::PlaneHit h = planar::hit_plane(light.p0, n, ref, wi, light.two_sided);
    if (!(h.t > 0.0f)) return 0.0f;
    const glm::vec2 b = barycentrics(light, h.point, n, len);
    if (b.x < 0.0f || b.y < 0.0f || b.x + b.y > 1.0f) return 0.0f;
    if (spherical_sampling(light, ref, 0.5f * len)) {
        const float omega = corners_from(light, ref, n).solid_angle;
        return omega > 0.0f ? 1.0f / omega : 0.0f;
    }
    return planar::pdf_of(h, 0.5f * len);
}

LightLeSample sample_le(const TriangleLight& light, glm::vec2 u_pos, glm::vec2 u_dir) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f) || !std::isfinite(len)) return {};
    const glm::vec2 b = sample_uniform_triangle(u_pos);
    const glm::vec3 p = light.p0 + b.x * e1 + b.y * e2;
    LightLeSample s = emission::leave_surface(p, c / len, 2.0f / len, radiance_at(light, b),
                                              light.two_sided, u_dir);
    s.offset = corner_offset(light);
    return s;
}

LightLePdf pdf_le(const TriangleLight& light, const glm::vec3& /*origin*/,
                  const glm::vec3& /*normal*/, const glm::vec3& direction) {
    const glm::vec3 c = glm::cross(light.p1 - light.p0, light.p2 - light.p0);
    const float len = glm::length(c);
    if (!(len > 0.0f) || !std::isfinite(len)) return {};
    return {2.0f / len, emission::direction_pdf(c / len, light.two_sided, direction)};
}

glm::vec3 power(const TriangleLight& light) {
    // Lambertian emitter: L pi per unit area and side (pbrt 4th ed. 12.5), the texture by
    // its estimated mean.
    const float area = 0.5f * glm::length(glm::cross(light.p1 - light.p0, light.p2 - light.p0));
    const float sides = light.two_sided ? 2.0f : 1.0f;
    return light.radiance * light.mean_texture * (sides * kPi * area);
}

LightBounds TriangleLight::bounds() const {
    // Centroid and the farthest corner: not the smallest sphere, but it contains the triangle.
    const glm::vec3 c = (p0 + p1 + p2) / 3.0f;
    const float r = std::max({glm::length(p0 - c), glm::length(p1 - c), glm::length(p2 - c)});
    LightBounds b = detail::finite_light_bounds(c, r, power(*this));
    const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
    // A degenerate triangle has no normal (and no power): no cone.
    detail::bound_planar(b, n, !two_sided && glm::dot(n, n) > 0.0f);
    return b;
}

}  // namespace librt
