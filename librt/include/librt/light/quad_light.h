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

/// A parallelogram area light: the points corner + s edge0 + t edge1 for s, t in [0, 1],
/// emitting a uniform radiance. Its front faces along edge0 x edge1; a one-sided light
/// emits from the front only. Scene::add_quad_light also adds the two triangles that are
/// its surface. Sampled uniformly by area: pdf per solid angle d^2 / (A |cos|).
struct QuadLight {
    glm::vec3 corner{0.0f};    ///< one corner
    glm::vec3 edge0{0.0f};     ///< first edge from the corner
    glm::vec3 edge1{0.0f};     ///< second edge from the corner
    glm::vec3 radiance{0.0f};  ///< emitted radiance L (W / (sr m^2)) per channel
    bool two_sided = false;    ///< emits from the back as well

    /// A surface: LightType::Area.
    [[nodiscard]] static constexpr LightType type() { return LightType::Area; }
    /// The unit front normal, edge0 x edge1 (the same at every point p).
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const {
        return glm::normalize(glm::cross(edge0, edge1));
    }
    /// The sphere through its corners about its centre; the front hemisphere when one-sided.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Nothing to learn of the scene.
    static void preprocess(const SceneSummary& /*scene*/) {}
};

/// Throws librt::Error naming the parameter and value if a vector is not finite, the
/// edges span no area, or the radiance is negative or not finite.
LIBRT_API void validate(const QuadLight& light);

/// A point drawn uniformly on the parallelogram, as a direction from ref; invalid when
/// ref is behind a one-sided light or in its plane.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const QuadLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// The solid-angle density of sample_li at ref for unit direction wi; 0 if wi misses.
[[nodiscard]] LIBRT_API float pdf_li(const QuadLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// A ray leaving the light (for paths that start there): a point uniform by area (pdf_pos
/// 1 / A), a direction cosine-weighted about the normal of the side it leaves (one-sided:
/// the front, pdf_dir cos / pi; two-sided: either side with probability 1/2, |cos| /
/// (2 pi)), radiance L. Invalid when the edges span no area.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const QuadLight& light, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray from `origin` on the light along unit `direction`:
/// pos 1 / A, dir as sample_le's (0 behind a one-sided light). The light's own normal is
/// used; `normal` is not looked at, nor whether origin lies on the light.
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const QuadLight& light, const glm::vec3& origin,
                                          const glm::vec3& normal, const glm::vec3& direction);
/// Total emitted power per channel: L pi A (times 2 when two-sided).
[[nodiscard]] LIBRT_API glm::vec3 power(const QuadLight& light);

}  // namespace librt
