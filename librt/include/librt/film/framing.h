#pragma once

#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/geometry/bbox.h>

#include <glm/vec3.hpp>

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

}  // namespace librt
