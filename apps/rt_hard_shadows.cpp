// The report's hard-shadow figure: the room and its four spheres lit by a point light,
// direct light only (one shadow ray per hit), one sample per pixel.
#include "common/cli.h"

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>

using namespace librt;

int main(int argc, char** argv) {
    apps::CommandLine command_line{"The report's hard shadows: point light, direct lighting only",
                                   "rt_hard_shadows"};
    apps::AppOptions options;
    options.spp = 1;
    options.output = "hard_shadows.png";
    apps::add_common_options(command_line.app(), options);
    return apps::run(command_line, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        if (options.guiding)
            throw Error("--guiding: rt_hard_shadows traces no paths to guide (direct light only)");
        Scene scene;
        apps::add_report_scene(scene, apps::LightKind::Point, options.power);
        scene.commit();
        DirectLighting integrator(DirectLightingSettings{options.bounces});
        return apps::render_and_write(scene, apps::camera_of(options), integrator, options);
    });
}
