#include "gltf/gltf_scene_materials.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/film/camera.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/material/texture.h>
#include <librt/scene/default_lighting.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

namespace librt {

namespace {

/// Luminous efficacy of 555 nm light, 683 lm/W: candela -> W/sr and lux -> W/m^2 the way
/// Blender's exporter converts (../shared/data/README.md), for PunctualLightUnits::Watts.
constexpr float kLumensPerWatt = 683.0f;

bool all_digits(const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// The camera the options choose, or nullptr for "none in the file: use the default".
const GltfCamera* choose_camera(const GltfScene& gltf, const std::string& wanted) {
    auto list = [&gltf]() {
        std::string names;
        for (std::size_t i = 0; i < gltf.cameras.size(); ++i) {
            names += (i == 0 ? "" : ", ") + std::to_string(i) + " " +
                     quote_untrusted(gltf.cameras[i].name);
        }
        return names.empty() ? std::string("none") : names;
    };
    if (wanted.empty()) return gltf.cameras.empty() ? nullptr : &gltf.cameras.front();
    const GltfCamera* found = nullptr;
    if (all_digits(wanted) && wanted.size() < 9) {
        const std::size_t i = std::stoul(wanted);
        if (i < gltf.cameras.size()) found = &gltf.cameras[i];
    } else {
        for (const GltfCamera& c : gltf.cameras) {
            if (c.name == wanted) {
                found = &c;
                break;
            }
        }
    }
    if (found == nullptr) {
        throw Error("camera = " + wanted + ": no such camera in the file (cameras: " + list() +
                    ")");
    }
    return found;
}

/// Image size: the options' when given, else the camera's aspect with the long side fixed.
void choose_size(const SceneFileOptions& o, float aspect, CameraSettings& c) {
    if (o.width > 0 && o.height > 0) {
        c.width = o.width;
        c.height = o.height;
        return;
    }
    const float a = std::isfinite(aspect) && aspect > 0.0f ? aspect : 1.0f;
    const int side = std::max(1, o.default_long_side);
    if (a >= 1.0f) {
        c.width = side;
        c.height = std::max(1, int(std::lround(float(side) / a)));
    } else {
        c.height = side;
        c.width = std::max(1, int(std::lround(float(side) * a)));
    }
}

/// Smallest |determinant| of a world transform librt inverts: below it the inverse (which
/// instances and normals need) overflows float or is noise.
constexpr double kMinDeterminant = 1e-30;

/// Why the linear part of `world` cannot be inverted in float, or "" when it can. The
/// determinant in double, so that the message gives its true value (in float a 1e30 scale's
/// overflows to infinity and a tiny one's underflows to 0).
std::string singular_reason(const glm::mat4& world) {
    const double det = glm::determinant(glm::dmat3(glm::mat3(world)));
    char text[32];
    std::snprintf(text, sizeof text, "%g", det);
    if (!std::isfinite(det)) return std::string("its world transform's determinant is ") + text;
    if (det == 0.0)
        return "its world transform is singular (determinant 0: scaled to zero or flattened)";
    if (std::abs(det) > double(std::numeric_limits<float>::max()))
        return std::string("its world transform's determinant ") + text +
               " overflows float (a scale too large to invert)";
    if (std::abs(det) < kMinDeterminant)
        return std::string("its world transform's determinant ") + text +
               " is below 1e-30 (a scale too small to invert)";
    return {};
}

/// True when `inst` places its mesh: a mesh index in range and an invertible transform (a
/// node scaled to zero places nothing; librt's instances need an inverse).
bool places_something(const GltfInstance& inst, std::size_t mesh_count) {
    if (inst.mesh < 0 || std::size_t(inst.mesh) >= mesh_count) return false;
    return singular_reason(inst.world).empty();
}

/// "nodes[4] 'name'": a node's JSON path and name, as messages give it.
std::string node_text(int node, const std::string& name) {
    return gltf_detail::named("nodes[" + std::to_string(node) + "]", name);
}

/// Bounds of a primitive's positions.
BBox bounds_of(const std::vector<glm::vec3>& positions) {
    BBox b;
    for (const glm::vec3& p : positions) b.extend(p);
    return b;
}

/// The box around `b`'s eight corners mapped by the affine `m`.
BBox transformed(const BBox& b, const glm::mat4& m) {
    BBox out;
    if (b.empty()) return out;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner((i & 1) != 0 ? b.hi.x : b.lo.x, (i & 2) != 0 ? b.hi.y : b.lo.y,
                               (i & 4) != 0 ? b.hi.z : b.lo.z);
        out.extend(glm::vec3(m * glm::vec4(corner, 1.0f)));
    }
    return out;
}

}  // namespace

LoadedScene scene_from_gltf(GltfScene gltf, const SceneFileOptions& options) {
    LoadedScene out;
    out.warnings = gltf.warnings;
    out.files_read = std::move(gltf.files_read);
    Scene& scene = out.scene;

    // Materials and their textures, added on first use (gltf_scene_materials.cpp).
    gltf_detail::MaterialBuilder materials(gltf, scene, out.warnings,
                                           {options.diffuse_model, options.solid_transmission});

    // One prototype per primitive, added once; its local bounds for framing.
    struct Prototype {
        std::uint32_t id;
        std::uint32_t material;
        BBox bounds;
    };
    std::vector<std::vector<Prototype>> prototypes(gltf.meshes.size());
    // A mesh placed by one node only is baked into world space (transform()) and added as
    // a mesh, not as a prototype and one instance: its rays then skip the instance's
    // transforms and hit finishing (cornell_pbr.glb, nine such meshes: the path tracer
    // 13 % faster). Meshes placed by several nodes stay prototypes, stored once.
    std::vector<std::size_t> placements(gltf.meshes.size(), 0);
    for (const GltfInstance& inst : gltf.instances)
        if (places_something(inst, gltf.meshes.size())) ++placements[std::size_t(inst.mesh)];
    struct Baked {
        TriangleMesh mesh;  ///< object space until its one node places it
        std::uint32_t material;
    };
    std::vector<std::vector<Baked>> baked(gltf.meshes.size());
    for (std::size_t mi = 0; mi < gltf.meshes.size(); ++mi) {
        for (std::size_t pi = 0; pi < gltf.meshes[mi].primitives.size(); ++pi) {
            GltfPrimitive& prim = gltf.meshes[mi].primitives[pi];
            if (prim.triangles.empty()) continue;
            const gltf_detail::SceneMaterial& material = materials.material(prim.material);
            const std::string where =
                "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "]";
            TriangleMesh mesh;
            const BBox bounds = bounds_of(prim.positions);
            mesh.positions = std::move(prim.positions);
            mesh.triangles = std::move(prim.triangles);
            mesh.normals = std::move(prim.normals);
            try {
                // The uv set and tangents its material's textures and normal map read.
                materials.attributes(prim, material, mesh, where);
                out.triangles_stored += mesh.triangles.size();
                if (placements[mi] == 1) {
                    baked[mi].push_back({std::move(mesh), material.id});
                } else {
                    prototypes[mi].push_back(
                        {scene.add_mesh_prototype(std::move(mesh)), material.id, bounds});
                }
            } catch (const Error& e) {
                throw Error(where + ": " + e.what());  // a mesh TriangleMesh refuses
            }
            prim = GltfPrimitive{};  // free the attributes librt does not use
        }
    }
    std::vector<bool> placed(gltf.instances.size(), false);
    for (std::size_t ii = 0; ii < gltf.instances.size(); ++ii) {
        const GltfInstance& inst = gltf.instances[ii];
        if (inst.mesh < 0 || std::size_t(inst.mesh) >= prototypes.size()) continue;
        const std::string node = node_text(inst.node, inst.node_name);
        if (const std::string why = singular_reason(inst.world); !why.empty()) {
            out.warnings.push_back(node + ": " + why + ": meshes[" + std::to_string(inst.mesh) +
                                   "] not placed");
            continue;
        }
        placed[ii] = true;
        try {
            for (Baked& b : baked[std::size_t(inst.mesh)]) {
                transform(b.mesh, inst.world);
                out.bounds.extend(b.mesh.bounds());
                out.triangles_placed += b.mesh.triangle_count();
                (void)scene.add_mesh(std::move(b.mesh), b.material);
            }
            for (const Prototype& p : prototypes[std::size_t(inst.mesh)]) {
                (void)scene.add_instance(p.id, inst.world, p.material);
                out.bounds.extend(transformed(p.bounds, inst.world));
            }
        } catch (const Error& e) {
            // Positions the transform takes beyond librt's range, say.
            throw Error(node + " placing meshes[" + std::to_string(inst.mesh) + "]: " + e.what());
        }
    }
    // Triangles placed by instances: per instance, its mesh's prototypes' triangles (the
    // baked meshes' are counted above).
    {
        std::vector<std::size_t> per_mesh(prototypes.size(), 0);
        for (std::size_t mi = 0; mi < prototypes.size(); ++mi) {
            for (const Prototype& p : prototypes[mi])
                per_mesh[mi] += scene.top_level().prototype_mesh(p.id).triangle_count();
        }
        for (std::size_t ii = 0; ii < gltf.instances.size(); ++ii) {
            if (placed[ii]) out.triangles_placed += per_mesh[std::size_t(gltf.instances[ii].mesh)];
        }
    }

    // Lights (KHR_lights_punctual). Watts: photometric to radiometric by 683 lm/W, candela ->
    // W/sr for point and spot, lux -> W/m^2 for directional (Blender's export convention);
    // Photometric: the numbers as they are, as web viewers show them (see
    // docs/render-your-own-scene.md, "Light units"). Spot and sun shine down the node's -z.
    const float divisor =
        options.light_units == PunctualLightUnits::Photometric ? 1.0f : kLumensPerWatt;
    std::size_t lights = 0;
    for (const GltfLight& l : gltf.lights) {
        const std::string who =
            gltf_detail::named(
                "extensions.KHR_lights_punctual.lights[" + std::to_string(l.light) + "]", l.name) +
            " placed by nodes[" + std::to_string(l.node) + "]";
        if (l.range > 0.0f && l.type != GltfLight::Type::Directional)
            out.warnings.push_back(who + ": range ignored (infinite)");
        const glm::vec3 position = glm::vec3(l.world * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        const glm::vec3 down_z = glm::vec3(l.world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f));
        const glm::vec3 radiometric = l.color * (l.intensity / divisor);
        try {
            if (l.type == GltfLight::Type::Point) {
                PointLight p;
                p.position = position;
                p.intensity = radiometric;
                scene.add_point_light(p);
            } else if (l.type == GltfLight::Type::Spot) {
                SpotLight spot;
                spot.position = position;
                spot.direction = down_z;
                spot.intensity = radiometric;
                spot.inner_angle = l.inner_cone_angle;
                spot.outer_angle = l.outer_cone_angle;
                scene.add_spot_light(spot);
            } else {
                DirectionalLight sun;
                sun.to_light = -down_z;
                sun.irradiance = radiometric;
                scene.add_directional_light(sun);
            }
        } catch (const Error& e) {
            // A degenerate node transform (e.g. scaled to zero) gives no direction.
            const std::string why = singular_reason(l.world);
            out.warnings.push_back(who + ": " + (why.empty() ? std::string(e.what()) : why) +
                                   ": ignored");
            continue;
        }
        ++lights;
    }

    // Camera: the file's (placed by its node), else one framing the bounds.
    // "auto": the framing camera even when the file has cameras.
    const GltfCamera* camera =
        options.camera == "auto" ? nullptr : choose_camera(gltf, options.camera);
    if (camera != nullptr) {
        const std::string who =
            gltf_detail::named("cameras[" + std::to_string(camera->camera) + "]", camera->name) +
            " placed by nodes[" + std::to_string(camera->node) + "]";
        // A view direction needs an invertible transform (a node scaled to zero has none).
        if (const std::string why = singular_reason(camera->world); !why.empty())
            throw Error(who + ": " + why + ": no view direction");
        CameraSettings& c = out.camera;
        out.camera_name =
            camera->name.empty() ? "camera " + std::to_string(camera->camera) : camera->name;
        const bool ortho = camera->type == GltfCamera::Type::Orthographic;
        choose_size(options, ortho ? camera->xmag / camera->ymag : camera->aspect_ratio, c);
        c.position = glm::vec3(camera->world * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        const glm::vec3 forward = glm::vec3(camera->world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f));
        c.look_at = c.position + glm::normalize(forward);
        c.up = glm::normalize(glm::vec3(camera->world * glm::vec4(0.0f, 1.0f, 0.0f, 0.0f)));
        if (ortho) {
            c.projection = Projection::Orthographic;
            c.xmag = camera->xmag;
            c.ymag = camera->ymag;
            // glTF's projection puts +-xmag and +-ymag at the image edges whatever its size.
            const float image_aspect = float(c.width) / float(c.height);
            if (std::abs(image_aspect * camera->ymag / camera->xmag - 1.0f) > 0.01f) {
                out.warnings.push_back(
                    "orthographic camera " + quote_untrusted(out.camera_name) +
                    ": xmag / ymag = " + std::to_string(camera->xmag / camera->ymag) +
                    " differs from the image's " + std::to_string(image_aspect) +
                    ": the image is stretched, as glTF's projection does");
            }
        } else {
            c.vertical_fov_degrees = glm::degrees(camera->yfov);
        }
        c.focal_distance = 1.0f;  // pinhole: unused
        // znear is a plane at that depth along the view axis, as CameraSettings::near_clip;
        // zfar (optional in glTF) likewise.
        c.near_clip = camera->znear;
        if (camera->zfar > camera->znear) c.far_clip = camera->zfar;
        // Checked here, naming the glTF camera, rather than when the app builds it.
        try {
            (void)Camera(c);
        } catch (const Error& e) {
            throw Error(who + ": " + e.what());
        }
    } else {
        CameraSettings size;
        choose_size(options, 4.0f / 3.0f, size);
        if (out.bounds.empty()) throw Error("the scene has no geometry to frame a camera on");
        out.camera = default_camera(out.bounds, size.width, size.height);
        out.camera_name = "default";
    }
    if (!options.view.empty()) {
        out.camera =
            view_camera(out.camera, camera == nullptr, out.bounds, options.view, out.camera_name);
    }
    // Decided by punctual lights alone: an emissive label or lamp does not light a model,
    // and emissive-only files came out black under the old rule (issue 42).
    if (lights == 0 && options.default_lighting)
        out.lighting_note = add_studio_lighting(scene, out.camera, options.background_visible);
    // Every name is quoted by named() above; this keeps any other text from the file (and
    // messages of the functions called) to one printable line each.
    for (std::size_t i = gltf.warnings.size(); i < out.warnings.size(); ++i)
        out.warnings[i] = printable(out.warnings[i], kMaxErrorBytes);
    return out;
}

}  // namespace librt
