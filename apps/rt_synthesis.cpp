// The report's synthesis: everything together. The room, its four spheres (diffuse,
// mirror, glass), a mesh on the floor, the light sphere, indirect light (5 bounces),
// Gaussian anti-aliasing, Gaussian depth of field (sigma 1, focal distance 55) and gamma
// 0.45; 80 samples per pixel at 512x512.
#include "common/cli.h"

#include <librt/integrator/integrators.h>

using namespace librt;

int main(int argc, char** argv) {
    apps::CommandLine command_line{"The report's synthesis image: every feature at once",
                                   "rt_synthesis"};
    apps::AppOptions options;
    options.spp = 80;
    options.output = "synthesis.png";
    apps::add_common_options(command_line.app(), options);
    apps::MeshOptions mesh_options;
    apps::add_mesh_options(command_line.app(), mesh_options);
    float lens_sigma = 1.0f;
    float focal_distance = 55.0f;
    command_line.add_option("--lens-sigma", lens_sigma,
                            "Standard deviation of the lens jitter (0 = pinhole)");
    command_line.add_option("--focal-distance", focal_distance,
                            "Distance along each ray that is sharp");
    return apps::run(command_line, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        apps::validate(mesh_options);
        CameraSettings camera = apps::camera_of(options);
        camera.pixel_jitter = PixelJitter::Gaussian;
        camera.lens = LensModel::Gaussian;
        camera.lens_sigma = lens_sigma;
        camera.focal_distance = focal_distance;
        (void)Camera(camera);  // validates --lens-sigma and --focal-distance
        Scene scene;
        apps::add_room(scene);
        apps::add_report_spheres(scene);
        apps::add_report_mesh(
            scene, apps::load_report_mesh(mesh_options.path, apps::placement_of(mesh_options)),
            Material::diffuse({0.9f, 0.6f, 0.3f}));
        apps::add_report_light(scene, apps::LightKind::Sphere, options.power);
        scene.commit();
        PathTracer integrator(apps::path_tracer_settings(options));
        return apps::render_and_write(scene, camera, integrator, options);
    });
}
