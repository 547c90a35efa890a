#pragma once

#include <librt/export.h>
#include <librt/geometry/ray.h>
#include <librt/sampling/filter.h>
#include <librt/sampling/sampler.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <limits>

namespace librt {

/// Where in a pixel a camera ray starts.
enum class PixelJitter {
    None,      ///< always the pixel centre (aliased edges, as the report's first figures)
    Gaussian,  ///< centre plus a Box-Muller Gaussian offset (the report's anti-aliasing)
    /// Centre plus an offset drawn from CameraSettings::pixel_filter (filter importance
    /// sampling). Gaussian above is this with a Gaussian of sigma = pixel_sigma and an
    /// infinite radius, drawing the same bits.
    Filter,
};

/// How the camera origin is spread for depth of field.
enum class LensModel {
    Pinhole,   ///< every ray starts at the camera position: everything sharp
    Gaussian,  ///< origin offset by a Gaussian in the camera's x-y plane (the report)
    Disk,      ///< origin uniform on a disk in the camera's x-y plane (a thin lens)
};

/// How camera rays leave the camera.
enum class Projection {
    /// Rays from one centre of projection through the image plane (the report's camera),
    /// spread by vertical_fov_degrees.
    Perspective,
    /// Parallel rays along the view direction from points of the camera's x-y plane
    /// (glTF's orthographic camera): the image spans [-xmag, xmag] x [-ymag, ymag] scene
    /// units around the position, whatever its size in pixels. No depth of field.
    Orthographic,
};

/// How CameraSettings::near_clip is measured.
enum class NearClipMode {
    /// A plane perpendicular to the view at depth near_clip in front of the lens plane:
    /// a ray at angle a to the view axis starts seeing at distance near_clip / cos(a).
    Plane,
    /// A distance along each ray from its origin (the lens point): every ray starts seeing
    /// at t = near_clip, as smallpt's published code starts its camera rays 140 along the
    /// unit direction. A sphere around a pinhole.
    Distance,
};

/// Everything that defines a camera. Defaults are the report's camera: at (0, 0, 55)
/// looking down -z, 60 degree vertical field of view, 512x512, no jitter, pinhole, no clip.
struct CameraSettings {
    glm::vec3 position{0.0f, 0.0f, 55.0f};  ///< centre of projection (the report's C)
    glm::vec3 look_at{0.0f, 0.0f, 0.0f};    ///< a point the optical axis passes through
    glm::vec3 up{0.0f, 1.0f, 0.0f};         ///< world "up"; must not be parallel to the view
    /// Perspective (the default) or orthographic.
    Projection projection = Projection::Perspective;
    /// Perspective only: full vertical field of view, in (0, 180).
    float vertical_fov_degrees = 60.0f;
    /// Orthographic only: half the image's width in scene units (glTF's xmag; finite, > 0).
    /// The left edge of pixel column 0 is at -xmag along right(), the right edge of the
    /// last column at +xmag: an image whose aspect differs from xmag / ymag is stretched,
    /// as glTF's projection matrix stretches it.
    float xmag = 1.0f;
    /// Orthographic only: half the image's height in scene units (glTF's ymag; finite, > 0).
    float ymag = 1.0f;
    int width = 512;                               ///< image width in pixels, in [1, 65536]
    int height = 512;                              ///< image height in pixels, in [1, 65536]
    PixelJitter pixel_jitter = PixelJitter::None;  ///< sub-pixel position of the rays
    float pixel_sigma = 0.5f;  ///< Gaussian pixel jitter's sigma in pixels (>= 0)
    /// Depth-of-field model; must be Pinhole for an orthographic camera (parallel rays
    /// have no centre of projection to focus through: depth of field is off there).
    LensModel lens = LensModel::Pinhole;
    float lens_sigma = 1.0f;       ///< Gaussian lens's sigma in scene units (>= 0)
    float lens_radius = 1.0f;      ///< disk lens's radius in scene units (>= 0)
    float focal_distance = 55.0f;  ///< distance along each ray that stays sharp (> 0)
    /// The filter PixelJitter::Filter samples offsets from (validated only when used).
    FilterSettings pixel_filter{};
    /// Near clip: hits closer than this are ignored (finite, >= 0), measured as
    /// near_clip_mode says: by default a depth in front of the lens plane, as smallpt's
    /// comment "start 140 units in front of the camera" describes. Named near_clip, not
    /// near: windows.h defines `near` and `far` as macros.
    float near_clip = 0.0f;
    /// Whether near_clip is a plane (the default) or a distance along each ray. It does
    /// not change far_clip, which is a plane in either mode (glTF's zfar is one).
    NearClipMode near_clip_mode = NearClipMode::Plane;
    /// Far clip plane: hits beyond this depth in front of the lens plane are ignored
    /// (> near_clip; +inf: none).
    float far_clip = std::numeric_limits<float>::infinity();
};

/// A primary ray and the weight its radiance takes in the pixel's plain mean.
struct CameraRay {
    Ray ray;              ///< unit direction; t_min and t_max set by the clip planes
    float weight = 1.0f;  ///< the pixel filter's FilterSample::weight (1 unless Mitchell)
};

/// The report's perspective camera, or an orthographic one. Pixel (x, y) = (column j,
/// row i), rows top to bottom. Perspective: the camera-space direction through it is
/// (j - W/2 + 0.5 + dx, -i + H/2 - 0.5 + dy, -H / (2 tan(fov/2))), rotated into the
/// world by the look-at basis. Orthographic: every ray has direction forward() and starts
/// at position + sx right() + sy true_up() with sx = (j - W/2 + 0.5 + dx) 2 xmag / W,
/// sy = (-i + H/2 - 0.5 + dy) 2 ymag / H. Immutable after construction; safe to share
/// across threads.
class LIBRT_API Camera {
public:
    /// Validates the settings; throws librt::Error naming the first bad parameter and
    /// its value.
    explicit Camera(const CameraSettings& settings);

    /// The primary ray for one sample of pixel (px, py). Always draws exactly two 2D
    /// samples from `sampler` (pixel jitter, then lens), used or not, so an integrator's
    /// random numbers do not change when jitter or depth of field is switched off.
    /// The direction is unit length. The clip planes at depths near_clip and far_clip
    /// (measured along the optical axis from the lens plane, which holds every ray
    /// origin) become, for a unit direction d, the distances t_min = near_clip /
    /// dot(d, forward) and t_max = far_clip / dot(d, forward) from the ray's origin (the
    /// lens point); dot(d, forward) > 0 for every camera ray. With NearClipMode::Distance
    /// t_min = near_clip for every ray instead. Without clips t_min = 0 and
    /// t_max = +inf, exactly as before. An orthographic ray's origin is on the camera's
    /// x-y plane and its direction is forward(), so its t is the depth itself. The filter
    /// weight is dropped: see sample_ray.
    [[nodiscard]] Ray generate_ray(int px, int py, Sampler& sampler) const {
        return sample_ray(px, py, sampler).ray;
    }

    /// generate_ray with the filter weight the sample's radiance must be multiplied by
    /// (not 1 only for a Mitchell pixel filter, whose negative lobes give negative weights).
    [[nodiscard]] CameraRay sample_ray(int px, int py, Sampler& sampler) const {
        // Two functions rather than a branch inside one: mixed into the perspective code,
        // the orthographic case slowed every perspective ray (docs/benchmarks.md, "Code
        // shaped by measurement").
        return settings_.projection == Projection::Orthographic ? orthographic_ray(px, py, sampler)
                                                                : perspective_ray(px, py, sampler);
    }

    /// The settings the camera was built from.
    [[nodiscard]] const CameraSettings& settings() const { return settings_; }
    /// Image width in pixels.
    [[nodiscard]] int width() const { return settings_.width; }
    /// Image height in pixels.
    [[nodiscard]] int height() const { return settings_.height; }
    /// Unit camera-space +x (image right) in world space.
    [[nodiscard]] const glm::vec3& right() const { return right_; }
    /// Unit camera-space +y (image up) in world space.
    [[nodiscard]] const glm::vec3& true_up() const { return up_; }
    /// Unit viewing direction (camera-space -z) in world space.
    [[nodiscard]] const glm::vec3& forward() const { return forward_; }
    /// Perspective only: the image plane's distance from the centre of projection in
    /// pixels, H / (2 tan(fov/2)) (the report's d; camera_importance.h inverts with it).
    [[nodiscard]] float image_plane_distance() const { return image_plane_distance_; }

private:
    // The sub-pixel offset of the jitter or filter for sample pixel_u; sets weight for a
    // filter (leaves it otherwise).
    [[nodiscard]] glm::vec2 pixel_offset(glm::vec2 pixel_u, float& weight) const;
    // sample_ray for a perspective camera (the report's) and for an orthographic one.
    [[nodiscard]] CameraRay perspective_ray(int px, int py, Sampler& sampler) const;
    [[nodiscard]] CameraRay orthographic_ray(int px, int py, Sampler& sampler) const;

    CameraSettings settings_;
    glm::vec2 ortho_pixel_size_{1.0f};  // (2 xmag / W, 2 ymag / H): scene units per pixel
    glm::vec3 right_{1.0f, 0.0f, 0.0f};
    glm::vec3 up_{0.0f, 1.0f, 0.0f};
    glm::vec3 forward_{0.0f, 0.0f, -1.0f};
    float image_plane_distance_ = 1.0f;  // H / (2 tan(fov/2)), in pixels
    PixelFilter filter_;                 // settings_.pixel_filter when it is used, else a box
    bool clipped_ = false;               // a clip plane is set: sample_ray computes t_min, t_max
};

}  // namespace librt
