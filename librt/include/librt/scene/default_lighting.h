#pragma once

#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/light/directional_light.h>
#include <librt/light/environment_light.h>
#include <librt/scene/scene.h>

#include <string>

// The studio lighting a scene file without lights of its own gets (SceneFileOptions::
// default_lighting): a neutral built-in sky, needing no file, plus a key light placed
// relative to the camera, so that the side the camera sees is lit whatever the file's
// orientation.

namespace librt {

/// The built-in sky: a 16 x 2048 grey equirectangular image (EnvironmentImage's layout), y up,
/// constant along each row: radiance 0.35 at the horizon rising to 0.6 at the zenith
/// (0.35 + 0.25 sin(elevation)), a ground falling from 0.35 at the horizon to 0.12 below.
/// Grey, so it tints nothing; brighter above, so tops read as tops.
[[nodiscard]] LIBRT_API EnvironmentImage studio_sky();

/// The key light for `camera`: a sun of irradiance 2 W/m^2 (grey) coming from above, left of
/// and behind the camera, along -0.5 right + 1.0 up + 0.7 back in the camera's own axes
/// (back: from look_at toward position). A white Lambertian surface facing it has radiance
/// 2 / pi from it, about the sky's own share again. Throws librt::Error for a camera whose
/// position equals its look_at or whose up is parallel to the view.
[[nodiscard]] LIBRT_API DirectionalLight studio_key_light(const CameraSettings& camera);

/// Adds studio_sky() (seen by camera rays too, as a neutral background, unless `sky_seen` is
/// false: then camera rays that leave see black, for a transparent background) and
/// studio_key_light(camera) to `scene`; returns the one-line note an app shows once.
LIBRT_API std::string add_studio_lighting(Scene& scene, const CameraSettings& camera,
                                          bool sky_seen = true);

}  // namespace librt
