// The report's mesh figure: a mesh standing on the floor of the room (fitted, scaled by 20
// and moved by (0, -10, 0)), light sphere, indirect light, anti-aliasing; 80 samples,
// 5 bounces. The report's character may not be redistributed: the default is a procedural
// Utah teapot of ~5.5k triangles; --mesh takes any OBJ (e.g. ../shared/data/stanford-bunny.obj).
// The mesh is traced through the BVH chosen by --bvh (median split by default, as in the
// report); with --compare-naive, before rendering, the app times that BVH against the
// linear scan, the report's "7x faster" (opt-in: on a large mesh the scan takes a minute).
#include "common/bvh_timing.h"
#include "common/cli.h"

#include <librt/integrator/integrators.h>

#include <CLI/CLI.hpp>

#include <map>

using namespace librt;

int main(int argc, char** argv) {
    CLI::App app{"The report's mesh in the room, with a BVH", "rt_mesh"};
    apps::AppOptions options;
    options.spp = 80;
    options.output = "mesh.png";
    apps::add_common_options(app, options);
    apps::MeshOptions mesh_options;
    apps::add_mesh_options(app, mesh_options);
    BvhBuilder builder = BvhBuilder::Median;
    const std::map<std::string, BvhBuilder> builders{{"median", BvhBuilder::Median},
                                                     {"sah", BvhBuilder::Sah}};
    app.add_option("--bvh", builder,
                   "BVH of the mesh, timed against the linear scan and then rendered with: median "
                   "(the report's split) or sah")
        ->transform(CLI::CheckedTransformer(builders, CLI::ignore_case));
    bool compare_naive = false;
    app.add_flag("--compare-naive", compare_naive,
                 "Before rendering, time the BVH against the brute-force linear scan (slow on "
                 "large meshes)");
    return apps::run(app, argc, argv, [&] {
        // Every parameter is checked before anything is loaded or allocated.
        apps::validate(options);
        apps::validate(mesh_options);
        CameraSettings camera = apps::camera_of(options);
        camera.pixel_jitter = PixelJitter::Gaussian;
        TriangleMesh mesh =
            apps::load_report_mesh(mesh_options.path, apps::placement_of(mesh_options));
        if (compare_naive && !options.quiet) apps::print_bvh_timing(mesh, builder, Camera(camera));

        Scene scene;
        apps::add_room(scene);
        apps::add_report_spheres(scene);
        apps::add_report_mesh(scene, std::move(mesh), Material::diffuse({0.9f, 0.6f, 0.3f}),
                              builder);
        apps::add_report_light(scene, apps::LightKind::Sphere, options.power);
        scene.commit();
        PathTracer integrator(apps::path_tracer_settings(options));
        return apps::render_and_write(scene, camera, integrator, options);
    });
}
