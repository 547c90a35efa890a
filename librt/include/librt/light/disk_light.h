#pragma once

#include <librt/export.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace librt {

struct LightBounds;   // src/light/light_bounds.h: the light sampler's
struct SceneSummary;  // scene_summary.h

/// A disk area light emitting a uniform radiance, its front along `normal`. Its surface,
/// for rays and for sampling alike, is the regular polygon of kDiskLightSides sides
/// inscribed in the circle (Scene::add_disk_light adds it as a triangle fan): the scene
/// has no exact disk primitive, and sampling the very polygon that rays hit keeps the
/// light and BSDF strategies estimating the same thing (the area differs from pi r^2 by
/// 0.16%).
struct DiskLight {
    glm::vec3 center{0.0f};               ///< centre of the disk
    glm::vec3 normal{0.0f, -1.0f, 0.0f};  ///< front direction (need not be unit)
    float radius = 1.0f;                  ///< circumradius of the polygon
    glm::vec3 radiance{0.0f};             ///< emitted radiance L (W / (sr m^2)) per channel
    bool two_sided = false;               ///< emits from the back as well

    /// A surface: LightType::Area.
    [[nodiscard]] static constexpr LightType type() { return LightType::Area; }
    /// The unit front normal (the same at every point p).
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const {
        return glm::normalize(normal);
    }
    /// The sphere of its circumradius; the front hemisphere when one-sided.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Nothing to learn of the scene.
    static void preprocess(const SceneSummary& /*scene*/) {}
};

/// Number of sides of the polygon that stands for a disk.
inline constexpr int kDiskLightSides = 64;

/// Throws librt::Error naming the parameter and value for a non-finite centre or normal,
/// a zero normal, a radius not > 0, or a negative or non-finite radiance.
LIBRT_API void validate(const DiskLight& light);

/// The corners of the polygon, counter-clockwise seen from the front.
[[nodiscard]] LIBRT_API glm::vec3 disk_light_corner(const DiskLight& light, int i);

/// A point drawn uniformly on the polygon, as a direction from ref; invalid when ref is
/// behind a one-sided light or in its plane.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const DiskLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// The solid-angle density of sample_li at ref for unit direction wi; 0 if wi misses.
[[nodiscard]] LIBRT_API float pdf_li(const DiskLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// A ray leaving the light (for paths that start there): a point uniform by area on the
/// polygon (pdf_pos 1 / A), a direction cosine-weighted about the normal of the side it
/// leaves (one-sided: the front, pdf_dir cos / pi; two-sided: either side with probability
/// 1/2, |cos| / (2 pi)), radiance L. Invalid for a degenerate radius or normal.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const DiskLight& light, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray from `origin` on the light along unit `direction`:
/// pos 1 / A, dir as sample_le's (0 behind a one-sided light). The light's own normal is
/// used; `normal` is not looked at, nor whether origin lies on the light.
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const DiskLight& light, const glm::vec3& origin,
                                          const glm::vec3& normal, const glm::vec3& direction);
/// Total emitted power per channel: L pi A (times 2 when two-sided).
[[nodiscard]] LIBRT_API glm::vec3 power(const DiskLight& light);

}  // namespace librt
