// The report's anti-aliasing figure: the soft-shadow scene with each camera ray offset
// by a Gaussian (Box-Muller, sigma = 0.5 pixel) from the pixel centre. One image per run:
// --no-jitter renders the aliased comparison (default name antialiasing_no_jitter.png);
// --zoom K also writes <output>_zoom.png, a K-times enlarged crop of the white sphere's
// edge where the staircase shows.
#include "common/cli.h"

#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>

#include <filesystem>

using namespace librt;

int main(int argc, char** argv) {
    apps::CommandLine command_line{
        "The report's anti-aliasing: Gaussian pixel jitter, sigma = 0.5 pixel", "rt_antialiasing"};
    apps::AppOptions options;
    options.spp = 30;
    apps::add_common_options(command_line.app(), options);
    bool no_jitter = false;
    float sigma = 0.5f;
    int zoom = 0;
    command_line.add_flag("--no-jitter", no_jitter,
                          "Every ray through the pixel centre (the aliased comparison)");
    command_line.add_option("--sigma", sigma, "Standard deviation of the pixel jitter, in pixels");
    command_line.add_option(
        "--zoom", zoom,
        "Also write <output>_zoom.png: the white sphere's edge enlarged this many times");
    return apps::run(command_line, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        CameraSettings camera = apps::camera_of(options);
        camera.pixel_jitter = no_jitter ? PixelJitter::None : PixelJitter::Gaussian;
        camera.pixel_sigma = sigma;
        (void)Camera(camera);  // validates --sigma
        if (options.output.empty()) {
            options.output = no_jitter ? "antialiasing_no_jitter.png" : "antialiasing.png";
            check_image_path(options.output);  // validate() checked a given -o
        }
        Scene scene;
        apps::add_report_scene(scene, apps::LightKind::Sphere, options.power);
        scene.commit();
        PathTracer integrator(apps::path_tracer_settings(options));
        const auto write_zoom = [&](const Image& image) {
            if (zoom <= 0) return;
            std::filesystem::path path(options.output);
            path.replace_filename(path.stem().string() + "_zoom" + path.extension().string());
            // The white sphere's upper-right edge sits at about (0.35 W, 0.44 H).
            const int side = std::max(8, image.height / 8);
            apps::write_zoomed_crop(path.string(), image, image.width * 35 / 100,
                                    image.height * 44 / 100, side, zoom, options.exposure);
            if (!options.quiet) std::printf("wrote %s\n", path.string().c_str());
        };
        return apps::render_and_write(scene, camera, integrator, options, write_zoom);
    });
}
