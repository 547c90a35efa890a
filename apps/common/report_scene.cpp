#include "report_scene.h"

#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/io/obj.h>
#include <librt/io/obj_materials.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <iostream>
#include <string>

namespace librt::apps {

void add_room(Scene& scene) {
    struct Wall {
        glm::vec3 center;
        float radius;
        glm::vec3 albedo;
    };
    // The report's room: (centre, radius, albedo), docs/scenes.md.
    const Wall walls[] = {
        {{0.0f, -1000.0f, 0.0f}, 990.0f, {0.0f, 0.0f, 1.0f}},  // floor, blue
        {{0.0f, 0.0f, -1050.0f}, 940.0f, {1.0f, 0.0f, 1.0f}},  // back wall, magenta
        {{0.0f, 0.0f, 1000.0f}, 940.0f, {1.0f, 1.0f, 0.0f}},   // behind the camera, yellow
        {{1000.0f, 0.0f, 0.0f}, 940.0f, {1.0f, 0.0f, 0.0f}},   // right wall, red
        {{-1000.0f, 0.0f, 0.0f}, 940.0f, {0.0f, 1.0f, 0.0f}},  // left wall, green
        {{0.0f, 1000.0f, 0.0f}, 940.0f, {1.0f, 1.0f, 1.0f}},   // ceiling, white
    };
    for (const Wall& w : walls) {
        (void)scene.add_sphere(Sphere{w.center, w.radius},
                               scene.add_material(Material::diffuse(w.albedo)));
    }
}

void add_report_spheres(Scene& scene) {
    (void)scene.add_sphere(Sphere{{-15.0f, -2.0f, 0.0f}, 8.0f},
                           scene.add_material(Material::diffuse(glm::vec3(1.0f))));
    (void)scene.add_sphere(Sphere{{25.0f, 0.0f, -50.0f}, 8.0f},
                           scene.add_material(Material::diffuse({0.0f, 1.0f, 0.0f})));
    (void)scene.add_sphere(Sphere{{-15.0f, 20.0f, 0.0f}, 7.0f},
                           scene.add_material(Material::mirror()));
    (void)scene.add_sphere(Sphere{{15.0f, 20.0f, 0.0f}, 7.0f},
                           scene.add_material(Material::dielectric(1.4f, /*fresnel=*/false)));
}

void add_report_light(Scene& scene, LightKind kind, float power) {
    if (kind == LightKind::Point) {
        scene.add_point_light(PointLight::from_power(kLightCenter, power));
    } else {
        (void)scene.add_sphere_light(
            SphereLight{Sphere{kLightCenter, kLightRadius},
                        SphereLight::radiance_for_power(power, kLightRadius)});
    }
}

void add_report_scene(Scene& scene, LightKind light, float power) {
    add_room(scene);
    add_report_spheres(scene);
    add_report_light(scene, light, power);
}

CameraSettings report_camera(int width, int height) {
    CameraSettings s;  // the defaults are the report's camera
    s.width = width;
    s.height = height;
    return s;
}

TriangleMesh default_mesh() {
    TriangleMesh mesh = make_teapot_with_triangles(5500);
    transform(mesh, make_transform(glm::vec3(1.0f), {0.0f, -45.0f, 0.0f}, glm::vec3(0.0f)));
    return mesh;
}

void place_mesh(TriangleMesh& mesh, const MeshPlacement& placement) {
    if (!(placement.fit >= 0.0f)) {
        throw Error("mesh fit = " + std::to_string(placement.fit) + ": must be >= 0");
    }
    if (!(placement.scale > 0.0f)) {
        throw Error("mesh scale = " + std::to_string(placement.scale) + ": must be > 0");
    }
    if (mesh.positions.empty()) throw Error("mesh has no vertices");
    if (placement.fit > 0.0f) {
        // Fit: bottom centre of the bounding box to the origin, largest side to `fit`.
        const BBox box = mesh.bounds();
        const glm::vec3 size = box.hi - box.lo;
        const float largest = std::max({size.x, size.y, size.z});
        if (!(largest > 0.0f)) throw Error("mesh has a degenerate bounding box");
        const glm::vec3 bottom_center{0.5f * (box.lo.x + box.hi.x), box.lo.y,
                                      0.5f * (box.lo.z + box.hi.z)};
        transform(mesh, glm::scale(glm::mat4(1.0f), glm::vec3(placement.fit / largest)) *
                            glm::translate(glm::mat4(1.0f), -bottom_center));
    }
    // The report's placement: p' = scale * p + offset (after the optional turn about y).
    transform(mesh, make_transform(glm::vec3(placement.scale),
                                   {0.0f, placement.rotate_y_degrees, 0.0f}, placement.offset));
}

TriangleMesh load_report_mesh(const std::filesystem::path& path, const MeshPlacement& placement) {
    TriangleMesh mesh = path.empty() ? default_mesh() : load_obj(path);
    place_mesh(mesh, placement);
    return mesh;
}

void add_report_mesh(Scene& scene, TriangleMesh mesh, const Material& fallback,
                     BvhBuilder builder) {
    const std::uint32_t fallback_id = scene.add_material(fallback);
    // load_obj gives faces without an MTL material one named "default": such a mesh
    // has no materials of its own.
    const bool own_materials =
        std::any_of(mesh.materials.begin(), mesh.materials.end(),
                    [](const MeshMaterial& m) { return m.name != "default"; });
    if (!own_materials) {
        (void)scene.add_mesh(std::move(mesh), fallback_id, builder);
    } else {
        // The library returns its warnings (textures that failed to load); the app prints.
        for (const std::string& w : add_mesh_with_mtl(scene, std::move(mesh), fallback_id).warnings)
            std::cerr << "warning: " << w << '\n';
    }
}

}  // namespace librt::apps
