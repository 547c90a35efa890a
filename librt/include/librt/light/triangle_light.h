#pragma once

#include <librt/export.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>
#include <librt/material/texture.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <memory>

namespace librt {

struct LightBounds;   // src/light/light_bounds.h: the light sampler's
struct SceneSummary;  // scene_summary.h

/// One emitting triangle of a mesh (Scene::commit makes one for every triangle whose
/// material emits). It emits `radiance` (times its emission texture at the emitting point,
/// when it has one) from its front, the side cross(p1 - p0, p2 - p0) points to, and, when
/// two-sided, from its back too, as Scene::shade makes an emissive material do when a ray
/// hits it. Sampled uniformly over the solid angle it subtends (spherical triangle, Arvo
/// 1995; pdf 1 / omega), so a point close to it (a ceiling just above a panel) gets light
/// samples of weight at most 2 pi L; when it looks small (area / distance to its centroid
/// squared below 0.1), uniformly by area (pdf per solid angle d^2 / (A |cos|)), about as
/// good there and cheaper.
struct TriangleLight {
    glm::vec3 p0{0.0f};        ///< first corner (Triangle's convention)
    glm::vec3 p1{0.0f};        ///< second corner
    glm::vec3 p2{0.0f};        ///< third corner
    glm::vec3 radiance{0.0f};  ///< emitted radiance L (W / (sr m^2)) per channel (the factor)
    /// Emits from the back as well (false: a glTF material that is not doubleSided).
    bool two_sided = true;
    /// Texture whose RGB multiplies radiance at the emitting point (the material's emission
    /// texture, shared by every triangle using it); null: the radiance is uniform.
    std::shared_ptr<const ImageTexture> texture;
    glm::vec2 uv0{0.0f, 0.0f};  ///< texture coordinate at p0 (the slot's transform applied)
    glm::vec2 uv1{1.0f, 0.0f};  ///< texture coordinate at p1
    glm::vec2 uv2{0.0f, 1.0f};  ///< texture coordinate at p2
    /// The texture's mean over the triangle, as power() uses it (mean_texture_estimate);
    /// 1 without a texture.
    glm::vec3 mean_texture{1.0f};

    /// A surface: LightType::Area.
    [[nodiscard]] static constexpr LightType type() { return LightType::Area; }
    /// The unit front normal, (p1 - p0) x (p2 - p0) (the same at every point p).
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const {
        return glm::normalize(glm::cross(p1 - p0, p2 - p0));
    }
    /// A sphere about the centroid through the farthest corner; the front hemisphere when
    /// one-sided.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Nothing to learn of the scene.
    static void preprocess(const SceneSummary& /*scene*/) {}
};

/// A point on the triangle (uniform in solid angle, or in area when it looks small), as a direction
/// from ref with its solid-angle density and the radiance emitted there; invalid when ref lies in
/// the triangle's plane, behind a one-sided triangle, or the triangle is degenerate. Its distance
/// is where the shadow ray must end: the emitting point less the rounding of a test against the
/// triangle along wi (ray_offset_scale of its largest vertex coordinates, over |cos| at the
/// emitter), and its end_slope 1 / |cos| makes spawn_ray_to take the origin's offset off too, so
/// a shadow ray from a surface just beside the triangle does not end on it.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const TriangleLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// The solid-angle density of sample_li at ref for unit direction wi; 0 if wi misses (or
/// meets a one-sided triangle's back).
[[nodiscard]] LIBRT_API float pdf_li(const TriangleLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// A ray leaving the light (for paths that start there): a point uniform by area (pdf_pos
/// 1 / A), a direction cosine-weighted about the normal of the side it leaves (one-sided:
/// the front, pdf_dir cos / pi; two-sided: either side with probability 1/2, |cos| /
/// (2 pi)), radiance radiance_at the point. Invalid for a degenerate triangle.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const TriangleLight& light, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray from `origin` on the triangle along unit
/// `direction`: pos 1 / A, dir as sample_le's (0 behind a one-sided triangle). The
/// triangle's own normal is used; `normal` is not looked at, nor whether origin lies on it.
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const TriangleLight& light, const glm::vec3& origin,
                                          const glm::vec3& normal, const glm::vec3& direction);
/// Total emitted power per channel: L pi A times the texture's mean, times 2 when two-sided.
[[nodiscard]] LIBRT_API glm::vec3 power(const TriangleLight& light);
/// The radiance emitted at barycentrics (b1, b2) (the point p0 + b1 (p1 - p0) + b2 (p2 - p0)).
[[nodiscard]] LIBRT_API glm::vec3 radiance_at(const TriangleLight& light, glm::vec2 b);
/// An estimate of the texture's mean over the triangle (for power only, which steers the
/// light choice and never biases it); 1 without a texture. Over more than 512 texels (and
/// a uv box of at most 2^18): the mean of the texels whose centres its uvs cover (exact
/// but for the texels along its edges); else the average of lookups at the centres of an
/// n x n stratification of the triangle, n^2 about twice the texels covered (n 4 to 32).
[[nodiscard]] LIBRT_API glm::vec3 mean_texture_estimate(const TriangleLight& light);
/// True when the light provably emits nothing anywhere: its radiance factor is 0, or every
/// texel a lookup within its corners' uv box can read is black (ImageTexture::max_over).
/// False when that is not known (a box of more than 2^14 texels is not searched).
[[nodiscard]] LIBRT_API bool emits_nowhere(const TriangleLight& light);

/// Which emissive triangles Scene::commit makes TriangleLights of (the light sampler's
/// lights). A triangle left out still emits wherever a ray hits it: BSDF sampling finds it,
/// and since no light strategy can, its emission there gets MIS weight 1 (the estimator
/// stays unbiased; only its variance there depends on the choice). Left out always: the
/// triangles that provably emit nothing (emits_nowhere: black over their whole texture
/// footprint), which are then no emitters at all. Both fractions below are of the scene's
/// own emissive triangles (scale-free, deterministic), and a mesh of equal triangles loses
/// none of its triangles to either; 0 turns a rule off. Each in [0, 1].
struct TriangleLightSettings {
    /// Left out: a triangle whose power (power(), the mean over channels) is below this
    /// fraction of the mean power of the emissive triangles of positive power (slivers, the
    /// bilinear fringe of a lamp's texels). Each emits less than f times the mean, so all
    /// of them together at most this fraction of the power the triangles emit.
    float negligible_power = 0.01f;
    /// Left out: a triangle whose mean radiance (its power over pi, area and sides) is
    /// below this fraction of the triangles' power-weighted mean radiance (the radiance
    /// the average emitted watt leaves with): a dim glow beside bright lamps, such as an
    /// 8-bit emission map's near-black noise (values 1-25 of 255 against white lamps).
    /// Light sampling gains little over BSDF sampling on such a wide, dim emitter, and its
    /// many triangles would crowd the light tree. A dim emitter that is the only light of
    /// its part of the scene (a large panel 100 times dimmer than a lamp elsewhere) is
    /// left out too: 0 keeps it.
    float negligible_radiance = 0.01f;
};

}  // namespace librt
