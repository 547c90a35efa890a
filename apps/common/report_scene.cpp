#include "report_scene.h"

#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/obj/obj.h>
#include <librt/obj/obj_materials.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

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

namespace {

/// A float as typed: shortest round-trip form.
std::string typed(float x) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
    return std::string(buffer, result.ptr);
}

/// "--mesh-fit = F, --mesh-scale = S" (what the user controls), for placement errors.
std::string placement_text(const MeshPlacement& p) {
    return "--mesh-fit = " + typed(p.fit) + ", --mesh-scale = " + typed(p.scale);
}

}  // namespace

void place_mesh(TriangleMesh& mesh, const MeshPlacement& placement) {
    if (!(placement.fit >= 0.0f) || !std::isfinite(placement.fit)) {
        throw Error("--mesh-fit = " + typed(placement.fit) + ": must be finite and >= 0");
    }
    if (!(placement.scale > 0.0f) || !std::isfinite(placement.scale)) {
        throw Error("--mesh-scale = " + typed(placement.scale) + ": must be finite and > 0");
    }
    if (mesh.positions.empty()) throw Error("the mesh has no vertices");
    // The placement's own matrices name their entries when they fail; the user typed
    // options, so the errors below name those.
    const auto apply = [&](const glm::mat4& m) {
        try {
            transform(mesh, m);
        } catch (const Error& e) {
            throw Error(placement_text(placement) + ": cannot place the mesh (" + e.what() + ")");
        }
    };
    if (placement.fit > 0.0f) {
        // Fit: bottom centre of the bounding box to the origin, largest side to `fit`.
        const BBox box = mesh.bounds();
        const glm::vec3 size = box.hi - box.lo;
        const float largest = std::max({size.x, size.y, size.z});
        if (!(largest > 0.0f)) {
            throw Error("all vertices of the mesh are at one point: --mesh-fit = " +
                        typed(placement.fit) + " cannot scale it (use --mesh-fit 0)");
        }
        const float factor = placement.fit / largest;
        if (!std::isfinite(factor) || !std::isfinite(largest)) {
            throw Error("--mesh-fit = " + typed(placement.fit) + ": the mesh's largest side, " +
                        typed(largest) + ", cannot be scaled to it in float");
        }
        const glm::vec3 bottom_center{0.5f * box.lo.x + 0.5f * box.hi.x, box.lo.y,
                                      0.5f * box.lo.z + 0.5f * box.hi.z};
        apply(glm::scale(glm::mat4(1.0f), glm::vec3(factor)) *
              glm::translate(glm::mat4(1.0f), -bottom_center));
    }
    // The report's placement: p' = scale * p + offset (after the optional turn about y).
    apply(make_transform(glm::vec3(placement.scale), {0.0f, placement.rotate_y_degrees, 0.0f},
                         placement.offset));
    for (const glm::vec3& p : mesh.positions) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw Error(placement_text(placement) +
                        ": the placed mesh's coordinates overflow float");
        }
    }
}

TriangleMesh load_report_mesh(const std::filesystem::path& path, const MeshPlacement& placement) {
    if (path.empty()) {
        TriangleMesh mesh = default_mesh();
        place_mesh(mesh, placement);
        return mesh;
    }
    // librt never prints: the app prints the loader's warnings.
    std::vector<std::string> warnings;
    ObjLoadOptions options;
    options.warnings = &warnings;
    TriangleMesh mesh = load_obj(path, options);
    for (const std::string& w : warnings) std::cerr << "warning: " << w << '\n';
    try {
        place_mesh(mesh, placement);
    } catch (const Error& e) {
        throw Error(path.string() + ": " + e.what());
    }
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
