#pragma once

#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/geometry/ray.h>
#include <librt/sampling/filter.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

// The camera seen from the light's side, for light tracing and bidirectional path tracing
// (the "t = 1" strategies): which raster position a ray from a lens point reaches, the
// camera's importance We and its pdfs, and a connection from a scene point to the lens.
// These invert Camera::sample_ray exactly; they are the perspective camera's only. An
// orthographic camera's directions are a delta (every ray is parallel to forward()), so no
// scene point connects to it: every function here returns nothing or 0 for it.
//
// Raster positions are continuous, x in [0, W) and y in [0, H): pixel (j, i) covers
// [j, j + 1) x [i, i + 1), rows top to bottom, as in sample_ray (its sample of pixel (j, i)
// with filter offset (dx, dy) is at raster (j + 0.5 + dx, i + 0.5 - dy): dy points up).
//
// The measurement these estimate. A pixel's value is the filtered mean
//   V(j, i) = integral over lens points o (density pdf_pos) and raster positions x of
//             h(x - centre(j, i)) L(o, direction(o, x)),
// with h = f / integral f the normalised pixel filter. Writing the raster integral over the
// direction instead (dx = W H pdf_dir(o, w) dw, pdf_dir below) and the direction over the
// scene point y it meets (dw = cos_y dA_y / d^2):
//   V(j, i) = E_o[ integral W H h(x(o, y) - centre(j, i)) We(o, y) cos_lens cos_y / d^2
//                  L(y -> o) dA_y ],   We = pdf_dir / cos_lens.
// So a light path whose last vertex y (density p_y per unit area, throughput beta including
// the BSDF at y) is joined to a lens point from sample_wi gives the film estimate
//   C = beta |cos_y| We cos_lens / d^2 / p_y = beta |cos_y| CameraWi::weight / p_y,
// an estimate of the integral over the whole film (pdf_pos cancels: the lens point is drawn
// with it); pixel (j, i) receives C W H h(raster - centre(j, i)). SplatFilm applies h and
// takes the W H: tracing N = spp W H light paths and adding C for each, its sums divided
// by spp are the pixel values (see splat_film.h).

namespace librt {

/// The densities of a camera ray (pdf_we): of its origin on the lens and of its direction.
struct CameraPdf {
    /// Density of the lens point per unit lens area: 1 for a pinhole (a delta, by
    /// convention), 1 / (pi r^2) for a disk lens, the 2D normal density for a Gaussian one.
    float pos = 0.0f;
    /// Solid-angle density of the direction when the raster position is uniform over the
    /// whole image (W x H pixels), given the lens point; 0 when it misses the image.
    float dir = 0.0f;
};

/// A connection from a scene point to a sampled lens point (sample_wi).
struct CameraWi {
    bool valid = false;          ///< false: behind the camera, clipped, or off the image
    glm::vec3 lens_point{0.0f};  ///< the point on the lens (the position for a pinhole)
    /// Where the camera ray from lens_point toward the reference point starts to see: its
    /// point on the near clip plane (or at distance near_clip for NearClipMode::Distance),
    /// or lens_point without a near clip. A join's shadow ray ends
    /// here, since the camera ray passes whatever lies before it.
    glm::vec3 view_start{0.0f};
    glm::vec3 wi{0.0f};       ///< unit direction from the reference point to lens_point
    float distance = 0.0f;    ///< from the reference point to lens_point
    glm::vec2 raster{0.0f};   ///< where the ray lens_point -> reference point meets the image
    float importance = 0.0f;  ///< We of that ray (camera_importance)
    float pdf_pos = 0.0f;     ///< density of lens_point per unit lens area (CameraPdf::pos)
    /// Solid-angle density at the reference point of having chosen this lens point:
    /// pdf_pos d^2 / cos_lens; 1 for a pinhole, whose lens point is a delta.
    float pdf = 0.0f;
    /// We cos_lens / d^2: what multiplies beta |cos_ref| / p_ref in the film estimate C
    /// (see the top of this header). Equals importance pdf_pos / pdf for a lens of finite
    /// size; for a pinhole it is what the delta leaves.
    float weight = 0.0f;
    bool delta = false;  ///< the lens point is a delta (a pinhole): no strategy but this one
};

/// True when the camera's lens points are a delta: a pinhole, or a disk or Gaussian lens
/// of size 0 (whose rays all start at the position, as the pinhole's do). Also true for an
/// orthographic camera, whose directions are the delta.
[[nodiscard]] LIBRT_API bool lens_is_delta(const Camera& camera);

/// Where the ray from a lens point (ray.origin: the position for a pinhole; a point of the
/// lens plane otherwise) in ray.direction (any length) meets the image: the pinhole
/// projection of its in-focus point. For a disk or Gaussian lens that is the point where
/// the ray crosses the sphere of radius focal_distance around the position, since
/// sample_ray aims each ray at position + focal_distance * (unit pinhole direction): an
/// in-focus sphere, not a plane. Nothing when the ray goes backwards or its raster lies
/// outside [-margin, W + margin) x [-margin, H + margin) (margin in pixels: 0 is the image;
/// a wider pixel filter needs the positions around it, see SplatFilm::margin(); a negative
/// margin keeps to the image's interior).
/// A lens point farther from the position than focal_distance (possible only with a huge
/// lens) can reach one direction from two in-focus points; the farther one is returned.
[[nodiscard]] LIBRT_API std::optional<glm::vec2> raster_of(const Camera& camera, const Ray& ray,
                                                           float margin = 0.0f);

/// The densities of a camera ray; both 0 when raster_of finds nothing (with this margin).
/// The ray's origin must be a lens point (as in raster_of); it is not checked to be on a
/// disk lens.
[[nodiscard]] LIBRT_API CameraPdf pdf_we(const Camera& camera, const Ray& ray, float margin = 0.0f);

/// The importance We(ray) = pdf_we(ray).dir / cos(ray, forward), for one lens point: it
/// integrates to 1 against cos over the directions that reach the image. 0 off the image.
[[nodiscard]] LIBRT_API float camera_importance(const Camera& camera, const Ray& ray,
                                                float margin = 0.0f);

/// Connects the scene point `ref` to the lens: draws a lens point from u_lens (the disk or
/// Gaussian lens offset sample_ray draws from its lens sample; ignored for a pinhole) and
/// returns it with the reversed ray's raster position, importance and densities. Invalid
/// when `ref` is behind the lens plane, outside the clips (its depth in front of the lens
/// plane is not in (near_clip, far_clip), or for NearClipMode::Distance its distance from
/// the lens point is not beyond near_clip or its depth not before far_clip: the test camera
/// rays' hits pass), or when
/// the raster is off the image grown by `margin`.
[[nodiscard]] LIBRT_API CameraWi sample_wi(const Camera& camera, const glm::vec3& ref,
                                           glm::vec2 u_lens, float margin = 0.0f);

/// The filter a light tracer splats with to match the camera's pixel sampling: the
/// camera's pixel_filter for PixelJitter::Filter; a Gaussian of sigma pixel_sigma and
/// infinite radius for PixelJitter::Gaussian; a box of radius 0.5 (the pixel) for
/// PixelJitter::None, whose rays all pass through pixel centres - a point sample a splat
/// cannot reproduce, the box is its nearest area filter (and so for a Gaussian of sigma 0).
[[nodiscard]] LIBRT_API FilterSettings splat_filter_settings(const Camera& camera);

}  // namespace librt
