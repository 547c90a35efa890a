#pragma once

// Private: the data of SphereLight::cuts, which sphere_light.h holds behind a pointer to
// an incomplete type (no app needs its layout); tests reach it through librt/src.

#include <librt/export.h>

#include <glm/ext/vector_double3.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <optional>

// Opaque spheres that bury part of a sphere light (smallpt's radius-600 light, of which
// only an 18-unit cap pokes through the ceiling ball). SphereLight::preprocess finds them
// among the scene's opaque spheres (SceneSummary); its sample_li then samples only the
// part of the light a shading point can see (docs/sampling.md, "Buried sphere lights").

namespace librt {

struct SphereLight;

/// An opaque analytic sphere S whose surface cuts a sphere light L (centre c_L, radius
/// r_L). With D = |c_L - c_S| and a = (c_L - c_S) / D, the light's point c_L + r_L n (n a
/// unit normal) lies inside ball S iff n . a <= h, because
/// |c_L + r_L n - c_S|^2 = D^2 + 2 D r_L (n . a) + r_L^2 <= r_S^2
/// <=> n . a <= h = (r_S^2 - D^2 - r_L^2) / (2 r_L D); the surfaces cut iff -1 < h < 1.
/// Everything in double, from the spheres' double data (smallpt's walls are radius 1e5).
struct SphereCut {
    glm::dvec3 center{0.0};               ///< c_S
    double radius = 0.0;                  ///< r_S
    double radius2 = 0.0;                 ///< r_S^2, as S's intersection test uses it
    glm::dvec3 axis{0.0, 0.0, 1.0};       ///< a = (c_L - c_S) / D, unit
    glm::dvec3 tangent{1.0, 0.0, 0.0};    ///< unit, orthogonal to axis
    glm::dvec3 bitangent{0.0, 1.0, 0.0};  ///< axis x tangent
    double h = 0.0;  ///< the light's part inside S is n . axis <= h; in (-1, 1)
    /// acos(-h): the angular radius of the inside part, a cap about -axis (the outside
    /// part's is pi minus it, about +axis).
    double inside_angle = 0.0;
};

/// At most this many cuts are kept per light (the most restrictive): a shading point
/// classifies itself against each of them per light sample.
inline constexpr int kMaxSphereCuts = 8;

/// A cap is sampled by area when it covers at most this fraction of the light's surface;
/// a larger one is left to the cone sampling of the whole light, which wastes at most
/// 3/4 of its samples there and is cheaper per sample.
inline constexpr double kMaxCapFraction = 0.25;

/// The cuts of one sphere light, most restrictive first (smallest min(inside, outside)
/// fraction of the light's surface), with which of their parts share no point.
struct SphereLightCuts {
    std::array<SphereCut, kMaxSphereCuts> cut{};  ///< the first `count` are valid
    int count = 0;                                ///< number of cuts, <= kMaxSphereCuts
    /// disjoint[i][s] has bit 2 j + t set when part s of cut i and part t of cut j share
    /// no point of the light (s, t: 1 the part inside the cut's sphere, 0 outside): a
    /// point bound to both sees none of it. Precomputed: a per-sample test is one AND.
    std::array<std::array<std::uint16_t, 2>, kMaxSphereCuts> disjoint{};
};

/// The cut of the light (centre, radius) by an opaque sphere (centre, squared radius), or
/// nothing when their surfaces do not cut (-1 < h < 1 fails, or the centres coincide).
[[nodiscard]] LIBRT_API std::optional<SphereCut> sphere_cut(const glm::dvec3& light_center,
                                                            double light_radius,
                                                            const glm::dvec3& center,
                                                            double radius2);

/// Builds a SphereLightCuts from up to any number of cuts: sorted most restrictive first,
/// cut to kMaxSphereCuts, with `disjoint` filled in.
[[nodiscard]] LIBRT_API SphereLightCuts make_sphere_light_cuts(const SphereCut* cuts, int count);

/// Half-width of the band around a cut sphere's surface within which shading point p is
/// not classified against it (its side is unknown): twice ray_offset_scale(p), since
/// p's float coordinates lie within a few ulps of max |p_i| of the true surface and the
/// rays leaving p start ray_offset_scale(p) off it, on either side.
[[nodiscard]] LIBRT_API double sphere_cut_band(const glm::vec3& p);

/// What part of a sphere light a shading point may see.
enum class CapKind : std::uint8_t {
    Whole,   ///< no usable cut: the cone of the whole light is sampled
    Cap,     ///< only the light's points with n . axis in [z0, z1]: sampled by area
    Hidden,  ///< the point can see none of the light
};

/// The part of a sphere light visible from a shading point (visible_cap).
struct VisibleCap {
    CapKind kind = CapKind::Whole;   ///< which case
    const SphereCut* cut = nullptr;  ///< the cut whose side bounds the cap (Cap only)
    double z0 = -1.0;                ///< lower bound of n . axis (Cap only)
    double z1 = 1.0;                 ///< upper bound of n . axis (Cap only)
};

/// Classifies p against each of the light's cuts (in double; skipping a cut when p is
/// within sphere_cut_band(p) of its surface or when p is inside the light): strictly
/// inside S, p sees only the light's part inside S (n . a <= h), strictly outside, only
/// the part outside (n . a >= h). Returns the smallest such cap when it covers at most
/// kMaxCapFraction of the light, Hidden when two of the caps p is bound to are disjoint,
/// else Whole. A light without cuts is Whole everywhere.
[[nodiscard]] LIBRT_API VisibleCap visible_cap(const SphereLight& light, const glm::vec3& p);

}  // namespace librt
