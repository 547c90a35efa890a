#pragma once

// The camera the AOV tests look through: at the origin down -z, pinhole, no pixel jitter.

#include <librt/film/camera.h>

namespace librt::testing {

/// A width x height pinhole camera at the origin looking down -z with no pixel jitter:
/// every sample of a pixel is the same ray.
inline CameraSettings axis_camera(int width = 8, int height = 6) {
    CameraSettings cs;
    cs.position = {0.0f, 0.0f, 0.0f};
    cs.look_at = {0.0f, 0.0f, -1.0f};
    cs.width = width;
    cs.height = height;
    return cs;
}

}  // namespace librt::testing
