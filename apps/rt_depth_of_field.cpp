// The report's depth-of-field figure: the camera origin jittered by a Gaussian (sigma = 1)
// in its x-y plane, each ray aimed at the point at focal distance 55 along the unjittered
// ray; the green sphere at z = -50 blurs, the objects near z = 0 stay sharp. --pinhole
// renders the comparison (default name depth_of_field_pinhole.png).
#include "common/cli.h"

#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>

using namespace librt;

int main(int argc, char** argv) {
    apps::CommandLine command_line{
        "The report's depth of field: Gaussian lens jitter, sigma 1, focal distance 55",
        "rt_depth_of_field"};
    apps::AppOptions options;
    options.spp = 80;
    apps::add_common_options(command_line.app(), options);
    bool pinhole = false;
    float lens_sigma = 1.0f;
    float focal_distance = 55.0f;
    command_line.add_flag("--pinhole", pinhole,
                          "No lens jitter: everything sharp (the comparison)");
    command_line.add_option("--lens-sigma", lens_sigma,
                            "Standard deviation of the lens jitter, scene units");
    command_line.add_option("--focal-distance", focal_distance,
                            "Distance along each ray that is sharp");
    return apps::run(command_line, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        CameraSettings camera = apps::camera_of(options);
        camera.pixel_jitter = PixelJitter::Gaussian;
        camera.lens = pinhole ? LensModel::Pinhole : LensModel::Gaussian;
        camera.lens_sigma = lens_sigma;
        camera.focal_distance = focal_distance;
        (void)Camera(camera);  // validates --lens-sigma and --focal-distance
        if (options.output.empty()) {
            options.output = pinhole ? "depth_of_field_pinhole.png" : "depth_of_field.png";
            check_image_path(options.output);  // validate() checked a given -o
        }
        Scene scene;
        apps::add_report_scene(scene, apps::LightKind::Sphere, options.power);
        scene.commit();
        PathTracer integrator(apps::path_tracer_settings(options));
        return apps::render_and_write(scene, camera, integrator, options);
    });
}
