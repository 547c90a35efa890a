// A glass sphere and a mirror sphere in the report's room, lit by a point light: the light
// they focus onto the floor and walls is a caustic, which a path tracer cannot find (no
// BSDF ray hits a point, and a shadow ray stops at the glass). Rendered twice: the plain
// path tracer (caustics_path.png: no caustic at all) and with caustic light paths traced
// from the light (caustics_split.png). Usage: caustics [samples per pixel] [width].

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/light/point_light.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) try {
    using librt::Material;
    const int spp = argc > 1 ? std::atoi(argv[1]) : 16;
    const int width = argc > 2 ? std::atoi(argv[2]) : 240;
    if (spp < 1 || width < 4 || width > 4096) {
        std::fprintf(stderr, "caustics: usage: caustics [spp >= 1] [width in 4..4096]\n");
        return 1;
    }
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
    scene.add_sphere({{-15, 0, -5}, 10}, scene.add_material(Material::dielectric(1.5f)));
    scene.add_sphere({{17, -2, -15}, 8}, scene.add_material(Material::mirror()));
    scene.add_point_light(librt::PointLight::from_power({-25, 28, -20}, 1.2e4f));
    scene.commit();

    librt::CameraSettings view;  // at (0, 0, 55) looking down -z
    view.width = width;
    view.height = width * 3 / 4;
    view.pixel_jitter = librt::PixelJitter::Gaussian;  // anti-aliasing
    librt::RenderSettings settings;
    settings.samples_per_pixel = spp;
    for (const bool split : {false, true}) {
        librt::PathTracerSettings pt;
        pt.caustic_paths.enabled = split;  // one light path per camera sample
        librt::PathTracer path_tracer(pt);
        librt::RenderStats stats;
        const librt::Image image =
            librt::render(scene, librt::Camera(view), path_tracer, settings, &stats);
        const std::string file = split ? "caustics_split.png" : "caustics_path.png";
        librt::write_png(file, image);  // gamma 0.45, clamped
        std::printf("wrote %s (%dx%d, %d spp) in %.2f s\n", file.c_str(), image.width, image.height,
                    spp, stats.seconds);
    }
    return 0;
} catch (const librt::Error& e) {
    std::fprintf(stderr, "caustics: %s\n", e.what());
    return 1;
}
