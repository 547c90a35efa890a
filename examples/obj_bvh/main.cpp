// Loads an OBJ (or makes a Utah teapot), stands it on a floor, builds the scene's BVHs
// and path traces it to a PNG.
//   obj_bvh [mesh.obj [output.png]]     (defaults: a procedural teapot, obj_bvh.png)

#include <librt/core/error.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/obj/obj.h>
#include <librt/obj/obj_materials.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <utility>

int main(int argc, char** argv) try {
    using librt::Material;
    const std::string output = argc > 2 ? argv[2] : "obj_bvh.png";

    // The mesh, scaled so its largest side is 2 and moved so it stands on y = 0 at the
    // origin, whatever units and placement the file uses.
    librt::TriangleMesh mesh = argc > 1 ? librt::load_obj(argv[1]) : librt::make_teapot(12);
    const librt::BBox box = mesh.bounds();
    const glm::vec3 size = box.diagonal();
    const float scale = 2.0f / std::max({size.x, size.y, size.z});
    const glm::vec3 bottom{box.center().x, box.lo.y, box.center().z};
    librt::transform(mesh,
                     librt::make_transform(glm::vec3(scale), glm::vec3(0.0f), -scale * bottom));
    const std::size_t triangles = mesh.triangle_count();

    librt::Scene scene;
    // Triangles with an MTL material keep it; the others are orange. Textures that fail to
    // load come back as warnings (the library never prints).
    const librt::MtlMeshResult added = librt::add_mesh_with_mtl(
        scene, std::move(mesh), scene.add_material(Material::diffuse({0.9f, 0.55f, 0.25f})));
    for (const std::string& w : added.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    // A grey floor (a quad facing +y) and a sphere light above, in front, to the left.
    scene.add_mesh(librt::make_quad({-20, 0, 20}, {40, 0, 0}, {0, 0, -40}),
                   scene.add_material(Material::diffuse(glm::vec3(0.6f))));
    scene.add_sphere_light({{{-3, 6, 5}, 1}, glm::vec3(40.0f)});

    // commit() builds a SAH BVH per mesh and one over all objects.
    const auto start = std::chrono::steady_clock::now();
    scene.commit();
    const std::chrono::duration<double, std::milli> build =
        std::chrono::steady_clock::now() - start;
    std::printf("%zu triangles, BVHs built in %.1f ms\n", triangles, build.count());

    librt::CameraSettings view;
    view.position = {0.0f, 1.8f, 5.5f};
    view.look_at = {0.0f, 0.6f, 0.0f};
    view.vertical_fov_degrees = 35.0f;
    view.width = 320;
    view.height = 240;
    view.pixel_jitter = librt::PixelJitter::Gaussian;
    librt::PathTracer path_tracer;
    librt::RenderSettings settings;
    settings.samples_per_pixel = 16;
    librt::RenderStats stats;
    const librt::Image image =
        librt::render(scene, librt::Camera(view), path_tracer, settings, &stats);
    librt::write_png(output, image);
    std::printf("wrote %s (%dx%d, %d spp) in %.2f s\n", output.c_str(), image.width, image.height,
                settings.samples_per_pixel, stats.seconds);
    return 0;
} catch (const librt::Error& e) {
    std::fprintf(stderr, "obj_bvh: %s\n", e.what());
    return 1;
}
