#include <librt/core/error.h>
#include <librt/io/gltf_scene.h>
#include <librt/render/texture.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>

namespace librt {

namespace {

/// Below this perceptual roughness a full metal is drawn as a perfect mirror (until the
/// GGX conductor lands, the nearest of today's kinds).
constexpr float kMirrorRoughness = 0.1f;

/// Luminous efficacy of 555 nm light, 683 lm/W: candela -> W/sr and lux -> W/m^2 the way
/// Blender's exporter converts (../shared/data/README.md).
constexpr float kLumensPerWatt = 683.0f;

glm::vec3 clamp01(const glm::vec3& c) { return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f)); }

bool all_digits(const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// The camera the options choose, or nullptr for "none in the file: use the default".
const GltfCamera* choose_camera(const GltfScene& gltf, const std::string& wanted) {
    auto list = [&gltf]() {
        std::string names;
        for (std::size_t i = 0; i < gltf.cameras.size(); ++i) {
            names += (i == 0 ? "" : ", ") + std::to_string(i) + " '" + gltf.cameras[i].name + "'";
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

/// The uvs a primitive's base colour texture is looked up with: its coordinate set, its
/// KHR_texture_transform, then v flipped (glTF's v runs down, ImageTexture's up).
std::vector<glm::vec2> texture_uvs(const GltfPrimitive& prim, const GltfTextureRef& ref) {
    const std::vector<glm::vec2>& src = ref.tex_coord == 1 ? prim.uv1 : prim.uv0;
    std::vector<glm::vec2> uvs;
    uvs.reserve(src.size());
    const glm::mat3 m = ref.has_transform ? ref.transform.matrix() : glm::mat3(1.0f);
    for (const glm::vec2& uv : src) {
        const glm::vec2 t = ref.has_transform ? glm::vec2(m * glm::vec3(uv, 1.0f)) : uv;
        uvs.emplace_back(t.x, 1.0f - t.y);
    }
    return uvs;
}

/// The material's base colour texture as linear texels times the factor, or an empty
/// texture when it has none that can be used.
ImageTexture base_color_texture(const GltfScene& gltf, const GltfMaterial& m) {
    const GltfTextureRef& ref = m.base_color_texture;
    if (!ref.valid() || std::size_t(ref.texture) >= gltf.textures.size()) return {};
    const int image = gltf.textures[std::size_t(ref.texture)].image;
    if (image < 0 || std::size_t(image) >= gltf.images.size()) return {};
    const GltfImage& img = gltf.images[std::size_t(image)];
    if (img.width <= 0 || img.height <= 0) return {};
    // sRGB decoding through a table: 256 values instead of a pow per texel channel.
    float table[256];
    for (int i = 0; i < 256; ++i) table[i] = srgb_to_linear(float(i) / 255.0f);
    const glm::vec3 factor = clamp01(glm::vec3(m.base_color_factor));
    std::vector<glm::vec3> texels(std::size_t(img.width) * std::size_t(img.height));
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const std::uint8_t* p = &img.rgba[4 * i];
        texels[i] = factor * glm::vec3(table[p[0]], table[p[1]], table[p[2]]);
    }
    return ImageTexture(img.width, img.height, std::move(texels));
}

/// Warnings for the parts of a material today's kinds cannot show.
void warn_unsupported(const GltfMaterial& m, std::size_t index, std::vector<std::string>& w) {
    const std::string who = "materials[" + std::to_string(index) + "] '" + m.name + "': ";
    if (m.emissive_texture.valid()) w.push_back(who + "emissive texture ignored (factor used)");
    if (m.normal_texture.valid()) w.push_back(who + "normal texture ignored");
    if (m.metallic_roughness_texture.valid())
        w.push_back(who + "metallic-roughness texture ignored (factors used)");
    if (m.transmission_texture.valid()) w.push_back(who + "transmission texture ignored");
    if (m.alpha_mode != GltfAlphaMode::Opaque)
        w.push_back(who + "alpha MASK/BLEND not supported yet: drawn opaque");
}

}  // namespace

Material material_from_gltf(const GltfMaterial& m, std::int32_t base_color_texture) {
    const glm::vec3 base = clamp01(glm::vec3(m.base_color_factor));
    Material out;
    if (m.transmission_factor > 0.0f) {
        out = Material::dielectric(m.ior > 0.0f ? m.ior : 1.5f, true, base);
    } else if (m.metallic_factor >= 1.0f && m.roughness_factor < kMirrorRoughness) {
        out = Material::mirror(base);
    } else {
        out = Material::diffuse(base);
        out.albedo_texture = base_color_texture;
    }
    // KHR_materials_emissive_strength scales the factor (the extension's definition).
    out.emission = glm::max(m.emissive_factor * m.emissive_strength, glm::vec3(0.0f));
    return out;
}

LoadedScene scene_from_gltf(GltfScene gltf, const SceneFileOptions& options) {
    LoadedScene out;
    out.warnings = gltf.warnings;
    Scene& scene = out.scene;

    // Scene materials by (glTF material, whether its texture is used); -1 = the default.
    const std::uint32_t default_material = scene.add_material(Material::diffuse(glm::vec3(0.8f)));
    std::vector<std::uint32_t> material_ids(gltf.materials.size(), kInvalidId);
    bool emissive = false;
    auto material_of = [&](int index) -> std::uint32_t {
        if (index < 0 || std::size_t(index) >= gltf.materials.size()) return default_material;
        std::uint32_t& id = material_ids[std::size_t(index)];
        if (id != kInvalidId) return id;
        const GltfMaterial& m = gltf.materials[std::size_t(index)];
        warn_unsupported(m, std::size_t(index), out.warnings);
        std::int32_t texture = -1;
        ImageTexture image = base_color_texture(gltf, m);
        if (!image.empty()) texture = scene.add_texture(std::move(image));
        const Material material = material_from_gltf(m, texture);
        emissive = emissive || material.emits();
        id = scene.add_material(material);
        return id;
    };

    // One prototype per primitive, added once; its local bounds for framing.
    struct Prototype {
        std::uint32_t id;
        std::uint32_t material;
        BBox bounds;
    };
    std::vector<std::vector<Prototype>> prototypes(gltf.meshes.size());
    for (std::size_t mi = 0; mi < gltf.meshes.size(); ++mi) {
        for (GltfPrimitive& prim : gltf.meshes[mi].primitives) {
            if (prim.triangles.empty()) continue;
            const std::uint32_t material = material_of(prim.material);
            TriangleMesh mesh;
            const bool textured = scene.material(material).albedo_texture >= 0;
            if (textured) {
                const GltfTextureRef& ref =
                    gltf.materials[std::size_t(prim.material)].base_color_texture;
                mesh.uvs = texture_uvs(prim, ref);
            }
            const BBox bounds = bounds_of(prim.positions);
            mesh.positions = std::move(prim.positions);
            mesh.triangles = std::move(prim.triangles);
            mesh.normals = std::move(prim.normals);
            out.triangles_stored += mesh.triangles.size();
            prototypes[mi].push_back({scene.add_mesh_prototype(std::move(mesh)), material, bounds});
            prim = GltfPrimitive{};  // free the attributes librt does not use
        }
    }
    std::vector<bool> placed(gltf.instances.size(), false);
    for (std::size_t ii = 0; ii < gltf.instances.size(); ++ii) {
        const GltfInstance& inst = gltf.instances[ii];
        if (inst.mesh < 0 || std::size_t(inst.mesh) >= prototypes.size()) continue;
        // A node scaled to zero (a common way to hide an object) places nothing; librt's
        // instances need an invertible transform.
        const float det = glm::determinant(glm::mat3(inst.world));
        if (!std::isfinite(det) || std::abs(det) < 1e-30f) {
            out.warnings.push_back("nodes[" + std::to_string(inst.node) + "] '" + inst.node_name +
                                   "': singular transform (zero scale): not placed");
            continue;
        }
        placed[ii] = true;
        for (const Prototype& p : prototypes[std::size_t(inst.mesh)]) {
            (void)scene.add_instance(p.id, inst.world, p.material);
            out.bounds.extend(transformed(p.bounds, inst.world));
        }
    }
    // Triangles placed: per instance, the triangles of its mesh's prototypes.
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

    // Lights (KHR_lights_punctual). Photometric to radiometric by 683 lm/W: candela -> W/sr
    // for point and spot, lux -> W/m^2 for directional (Blender's export convention, see
    // docs/render-your-own-scene.md). Spot and sun shine down the node's local -z.
    std::size_t lights = 0;
    for (const GltfLight& l : gltf.lights) {
        const std::string who = "light '" + l.name + "'";
        if (l.range > 0.0f && l.type != GltfLight::Type::Directional)
            out.warnings.push_back(who + ": range ignored (infinite)");
        const glm::vec3 position = glm::vec3(l.world * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        const glm::vec3 down_z = glm::vec3(l.world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f));
        const glm::vec3 radiometric = l.color * (l.intensity / kLumensPerWatt);
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
            out.warnings.push_back(who + ": " + e.what() + ": ignored");
            continue;
        }
        ++lights;
    }
    if (lights == 0 && !emissive && !out.bounds.empty()) {
        scene.add_point_light(default_light(out.bounds));
        out.warnings.emplace_back(
            "no supported light or emissive surface in the file: added a default point light");
    }

    // Camera: the file's (placed by its node), else one framing the bounds.
    const GltfCamera* camera = choose_camera(gltf, options.camera);
    if (camera != nullptr) {
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
                    "orthographic camera '" + out.camera_name +
                    "': xmag / ymag = " + std::to_string(camera->xmag / camera->ymag) +
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
    } else {
        CameraSettings size;
        choose_size(options, 4.0f / 3.0f, size);
        if (out.bounds.empty()) throw Error("the scene has no geometry to frame a camera on");
        out.camera = default_camera(out.bounds, size.width, size.height);
        out.camera_name = "default";
    }
    return out;
}

}  // namespace librt
