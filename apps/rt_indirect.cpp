// The report's indirect-light figure: the point light plus cosine-weighted diffuse
// bounces (5 bounces, 30 samples per pixel).
#include "common/cli.h"

#include <librt/integrator/integrators.h>

using namespace librt;

int main(int argc, char** argv) {
    apps::CommandLine command_line{"The report's indirect lighting: point light, path tracing",
                                   "rt_indirect"};
    apps::AppOptions options;
    options.spp = 30;
    options.output = "indirect.png";
    apps::add_common_options(command_line.app(), options);
    return apps::run(command_line, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        Scene scene;
        apps::add_report_scene(scene, apps::LightKind::Point, options.power);
        scene.commit();
        PathTracer integrator(apps::path_tracer_settings(options));
        return apps::render_and_write(scene, apps::camera_of(options), integrator, options);
    });
}
