// The report's soft-shadow figure: the point light replaced by a light sphere of radius
// 10, sampled at a random point per shadow ray (5 bounces, 30 samples per pixel).
#include "common/cli.h"

#include <librt/integrator/integrators.h>

using namespace librt;

int main(int argc, char** argv) {
    apps::CommandLine command_line{
        "The report's soft shadows: a light sphere of radius 10, path tracing", "rt_soft_shadows"};
    apps::AppOptions options;
    options.spp = 30;
    options.output = "soft_shadows.png";
    apps::add_common_options(command_line.app(), options);
    return apps::run(command_line, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        Scene scene;
        apps::add_report_scene(scene, apps::LightKind::Sphere, options.power);
        scene.commit();
        PathTracer integrator(apps::path_tracer_settings(options));
        return apps::render_and_write(scene, apps::camera_of(options), integrator, options);
    });
}
