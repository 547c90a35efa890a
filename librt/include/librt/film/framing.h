#pragma once

#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/geometry/bbox.h>

#include <glm/vec3.hpp>

#include <optional>

// A camera for a scene that brings none: the bounds framed from a default direction, as glTF
// viewers show a model (it fills the frame).

namespace librt {

/// The direction frame_bounds looks from by default (from the target toward the camera):
/// the model's front, +z (glTF's "front" axis), raised 15 degrees above the horizon, as
/// model-viewer's default orbit (azimuth 0, 75 degrees from the zenith). Unit length.
[[nodiscard]] LIBRT_API glm::vec3 default_view_direction();

/// How frame_bounds fits the bounds.
struct FramingOptions {
    float vertical_fov_degrees = 40.0f;  ///< the camera's, in (0, 179)
    /// Unit-free share of each half field of view left empty around the bounds, in [0, 0.5):
    /// 0.05 keeps the box 5 % inside the frame's edges.
    float margin = 0.05f;
    /// From the target toward the camera (need not be unit); not parallel to +y is best
    /// (+y and -y take -z as the image's up).
    glm::vec3 view_from = default_view_direction();
};

/// A pinhole camera (width x height pixels, y up) that sees all eight corners of `bounds`
/// from `options.view_from` and fills the frame: the camera is at the closest distance where
/// every corner projects inside the frame shrunk by the margin (so the box touches it on at
/// least one side), its optical axis moved sideways so that the projected box is centred.
/// focal_distance is the distance to the framed centre. Throws librt::Error naming the
/// parameter for an empty or non-finite box, a bad size, field of view or margin, or a zero
/// view direction.
[[nodiscard]] LIBRT_API CameraSettings frame_bounds(const BBox& bounds, int width, int height,
                                                    const FramingOptions& options = {});

/// A viewpoint the user gives instead of (or on top of) the chosen camera's: apply_view.
/// Every field unset leaves the camera as it is.
struct ViewOptions {
    /// Where the camera stands (finite). Without look_at it looks at the framed bounds'
    /// centre.
    std::optional<glm::vec3> look_from;
    /// A point the optical axis passes through (finite); differs from the position.
    std::optional<glm::vec3> look_at;
    /// Full vertical field of view in degrees, in (0, 179); perspective cameras only.
    std::optional<float> vertical_fov_degrees;
    /// Frame the bounds (frame_bounds) from default_view_direction() turned by this many
    /// degrees about +y, counter-clockwise seen from above (90: from +x), in [-360, 360].
    /// Replaces the chosen camera; with look_from or look_at it is refused.
    std::optional<float> orbit_degrees;

    /// True when no field is set.
    [[nodiscard]] bool empty() const {
        return !look_from && !look_at && !vertical_fov_degrees && !orbit_degrees;
    }
};

/// `camera` with `view` applied, for a scene of world bounds `bounds` (the image size is
/// kept). orbit_degrees reframes the bounds from the turned direction (vertical_fov_degrees,
/// or 40, as its field of view); `framed` says that `camera` is itself frame_bounds' camera
/// for these bounds, so that a new field of view alone reframes it (the model still fills
/// the frame) rather than zooming. look_from and look_at set the position and target (look_from
/// alone aims at the bounds' centre); the image's up stays world +y, or -z looking straight
/// down or up. Throws librt::Error naming the field ("look_from", "vertical_fov_degrees",
/// ...) and its value for a non-finite point, a position equal to its target, a field of view
/// out of range or on an orthographic camera, an orbit out of range or given with a point,
/// or bounds frame_bounds refuses when it is needed.
[[nodiscard]] LIBRT_API CameraSettings apply_view(const CameraSettings& camera, bool framed,
                                                  const BBox& bounds, const ViewOptions& view);

}  // namespace librt
