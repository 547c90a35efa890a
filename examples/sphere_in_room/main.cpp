// A white sphere in a coloured room lit by a sphere light, path traced and written to
// sphere_in_room.png. The walls are huge spheres, as in the report librt grew out of.

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>

#include <cstdio>

int main() try {
    using librt::Material;
    librt::Scene scene;
    struct Wall {
        glm::vec3 center;
        float radius;
        glm::vec3 albedo;
    };
    const Wall walls[] = {
        {{0, -1000, 0}, 990, {0.8f, 0.8f, 0.8f}},  // floor
        {{0, 1000, 0}, 960, {0.8f, 0.8f, 0.8f}},   // ceiling
        {{0, 0, -1000}, 960, {0.8f, 0.8f, 0.8f}},  // back
        {{0, 0, 1000}, 940, {0.8f, 0.8f, 0.8f}},   // behind the camera
        {{-1000, 0, 0}, 960, {0.8f, 0.2f, 0.2f}},  // left, red
        {{1000, 0, 0}, 960, {0.2f, 0.7f, 0.2f}},   // right, green
    };
    for (const Wall& w : walls) {
        scene.add_sphere({w.center, w.radius}, scene.add_material(Material::diffuse(w.albedo)));
    }
    scene.add_sphere({{0, 0, 0}, 10}, scene.add_material(Material::diffuse({0.9f, 0.9f, 0.9f})));
    scene.add_sphere_light({{{-12, 28, 20}, 5}, glm::vec3(18.0f)});
    scene.commit();

    librt::CameraSettings view;  // at (0, 0, 55) looking down -z
    view.width = 320;
    view.height = 240;
    view.pixel_jitter = librt::PixelJitter::Gaussian;  // anti-aliasing
    librt::PathTracer path_tracer;                     // paths ended by roulette
    librt::RenderSettings settings;                    // Sobol' samples, adaptive sampling
    settings.samples_per_pixel = 16;
    librt::RenderStats stats;
    const librt::Image image =
        librt::render(scene, librt::Camera(view), path_tracer, settings, &stats);
    librt::write_png("sphere_in_room.png", image);  // gamma 0.45, clamped
    std::printf("wrote sphere_in_room.png (%dx%d, %d spp) in %.2f s\n", image.width, image.height,
                settings.samples_per_pixel, stats.seconds);
    return 0;
} catch (const librt::Error& e) {
    std::fprintf(stderr, "sphere_in_room: %s\n", e.what());
    return 1;
}
