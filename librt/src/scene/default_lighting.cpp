#include <librt/core/error.h>
#include <librt/scene/default_lighting.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {

EnvironmentImage studio_sky() {
    EnvironmentImage sky;
    // Rows of 0.09 degrees: the radiance steps between them (at most 0.0024, in the ground's
    // fall below the horizon, 1.53 per radian) stay under an 8-bit step of the sRGB-encoded
    // background; 32 rows showed as bands behind a model.
    sky.width = 16;
    sky.height = 2048;
    sky.pixels.resize(std::size_t(sky.width) * std::size_t(sky.height));
    for (int y = 0; y < sky.height; ++y) {
        // Row y covers theta in [pi y / h, pi (y + 1) / h) from +y: its centre's elevation.
        const double theta = 3.14159265358979323846 * (double(y) + 0.5) / double(sky.height);
        const double elevation = 0.5 * 3.14159265358979323846 - theta;
        // Continuous at the horizon (0.35 from both sides); the ground darkens within about
        // 9 degrees below it (e-folding), as a floor seen far away.
        const double l = elevation >= 0.0 ? 0.35 + 0.25 * std::sin(elevation)
                                          : 0.12 + 0.23 * std::exp(elevation / 0.15);
        for (int x = 0; x < sky.width; ++x)
            sky.pixels[std::size_t(y) * std::size_t(sky.width) + std::size_t(x)] =
                glm::vec3(float(l));
    }
    return sky;
}

DirectionalLight studio_key_light(const CameraSettings& camera) {
    const glm::vec3 view = camera.look_at - camera.position;
    const glm::vec3 right = glm::cross(view, camera.up);
    if (!(glm::dot(view, view) > 0.0f) || !(glm::dot(right, right) > 0.0f))
        throw Error("studio_key_light: the camera's view direction is zero or parallel to up");
    const glm::vec3 back = -glm::normalize(view);
    const glm::vec3 r = glm::normalize(right);
    const glm::vec3 up = glm::cross(r, -back);  // the image's up, orthogonal to the view
    DirectionalLight key;
    key.to_light = glm::normalize(-0.5f * r + 1.0f * up + 0.7f * back);
    key.irradiance = glm::vec3(2.0f);
    return key;
}

std::string add_studio_lighting(Scene& scene, const CameraSettings& camera, bool sky_seen) {
    const DirectionalLight key = studio_key_light(camera);
    scene.add_environment_light(EnvironmentLight::from_image(studio_sky()), sky_seen);
    scene.add_directional_light(key);
    return "no light in the file: lit by the default studio lighting (a built-in grey sky and a "
           "key light from above left of the camera)";
}

}  // namespace librt
