#pragma once

#include <librt/export.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_type.h>
#include <librt/sampling/distribution.h>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <vector>

namespace librt {

struct LightBounds;   // src/light/light_bounds.h: the light sampler's
struct SceneSummary;  // scene_summary.h

/// An equirectangular radiance image (W / (sr m^2) per channel), rows top to bottom. Pixel
/// (x, y) covers u in [x / w, (x + 1) / w), v in [y / h, (y + 1) / h) with, in the light's
/// own frame (+y up), theta = pi v from +y and phi = 2 pi u: direction
/// (sin theta cos phi, cos theta, -sin theta sin phi). io/hdr_image.h loads one.
struct EnvironmentImage {
    int width = 0;                  ///< pixels per row
    int height = 0;                 ///< rows
    std::vector<glm::vec3> pixels;  ///< width * height, row-major
};

/// What an EnvironmentLight shares among its copies: the image and its sampling density.
struct EnvironmentData {
    EnvironmentImage image;         ///< empty for a constant environment
    glm::vec3 constant{0.0f};       ///< the radiance of a constant environment
    Distribution2D density;         ///< over (u, v), proportional to luminance * sin(theta)
    glm::vec3 mean_radiance{0.0f};  ///< solid-angle mean of the radiance (before scale)
};

/// The light of everything a ray that leaves the scene sees: an image around the scene or
/// a constant colour, turned by `rotation` (light frame to world) and scaled by `scale`.
/// An image is importance-sampled by a piecewise-constant 2D density proportional to
/// luminance * sin(theta) (pbrt 4th ed. 12.5.2; the sin(theta) undoes the equirectangular
/// map's stretching at the poles); a constant one uniformly over the sphere. Radiance is
/// piecewise constant over pixels (nearest lookup), so the density matches it exactly.
struct EnvironmentLight {
    std::shared_ptr<const EnvironmentData> data;  ///< image and density; null: black
    glm::mat3 rotation{1.0f};                     ///< light frame to world (orthonormal)
    float scale = 1.0f;                           ///< multiplies the radiance
    float scene_radius = 0.0f;                    ///< set by preprocess, for power()

    /// LightType::Infinite: every direction, seen by escaping rays.
    [[nodiscard]] static constexpr LightType type() { return LightType::Infinite; }
    /// 0: a light at infinity has no surface in the scene (its rays start on a disk facing
    /// along them, LightLeSample::normal).
    [[nodiscard]] static glm::vec3 surface_normal(const glm::vec3& /*p*/) {
        return glm::vec3(0.0f);
    }
    /// At infinity, every direction.
    [[nodiscard]] LIBRT_API LightBounds bounds() const;
    /// Takes the scene's radius, which power() needs.
    LIBRT_API void preprocess(const SceneSummary& scene);

    /// An environment of constant radiance.
    [[nodiscard]] LIBRT_API static EnvironmentLight constant(const glm::vec3& radiance);
    /// An environment from an equirectangular image (validated: size, finite and >= 0
    /// pixels; librt::Error naming the parameter otherwise).
    [[nodiscard]] LIBRT_API static EnvironmentLight from_image(
        EnvironmentImage image, const glm::mat3& rotation = glm::mat3(1.0f), float scale = 1.0f);
};

/// The rotation (light frame to world) that turns an environment by `degrees` about +y (world
/// up), counter-clockwise seen from above (right-handed): what the unturned environment shows
/// along +x is then seen along (cos a, 0, -sin a). rt_render's --env-rotate.
[[nodiscard]] LIBRT_API glm::mat3 rotation_about_up(float degrees);

/// Throws librt::Error for a missing data, a non-finite or negative scale, or a rotation
/// that is not orthonormal.
LIBRT_API void validate(const EnvironmentLight& light);

/// A direction drawn from the environment's density, at infinite distance.
[[nodiscard]] LIBRT_API LightLiSample sample_li(const EnvironmentLight& light, const glm::vec3& ref,
                                                glm::vec2 u);
/// The solid-angle density of sample_li for unit direction wi: p(u, v) / (2 pi^2 sin theta).
[[nodiscard]] LIBRT_API float pdf_li(const EnvironmentLight& light, const glm::vec3& ref,
                                     const glm::vec3& wi);
/// What a ray escaping along unit direction dir sees.
[[nodiscard]] LIBRT_API glm::vec3 escaped_radiance(const EnvironmentLight& light,
                                                   const glm::vec3& dir);
/// A ray from the environment into the scene (for paths that start there): a direction
/// toward the environment wi drawn as sample_li draws it (pdf_dir its solid-angle density,
/// radiance what arrives along it), the ray going -wi from a point uniform on the disk of
/// radius R perpendicular to wi at center + R wi (pdf_pos 1 / (pi R^2)). Invalid without
/// data or for a degenerate scene sphere.
[[nodiscard]] LIBRT_API LightLeSample sample_le(const EnvironmentLight& light,
                                                const SceneSphere& scene, glm::vec2 u_pos,
                                                glm::vec2 u_dir);
/// The densities sample_le gives a ray along unit `direction`: pos 1 / (pi R^2) (origin
/// and normal are not looked at), dir pdf_li of -direction.
[[nodiscard]] LIBRT_API LightLePdf pdf_le(const EnvironmentLight& light, const SceneSphere& scene,
                                          const glm::vec3& origin, const glm::vec3& normal,
                                          const glm::vec3& direction);
/// Power through the scene's bounding disk: pi R^2 times 4 pi times the mean radiance
/// (an estimate for the light sampler, as pbrt's).
[[nodiscard]] LIBRT_API glm::vec3 power(const EnvironmentLight& light);

}  // namespace librt
