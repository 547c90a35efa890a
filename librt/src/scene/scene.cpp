#include "material/bsdf_dispatch.h"

#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/material/bsdf.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <variant>

namespace librt {
namespace {

// Whether hits on a sphere of this material need its uv: for a texture lookup.
bool needs_uv(const Material& m) { return m.albedo_texture >= 0 || m.varies_per_hit(); }

// Whether a triangle of this material is light-sampled: every emitter (a TriangleLight
// carries the material's one-sidedness and emission texture) but a cut-out one, whose
// holes rays pass through: a light sample there would count light no ray can see.
// An unlit surface (glTF KHR_materials_unlit) is not either: it shows its colour, and
// BSDF sampling finds what little light it throws (docs/materials-and-lights.md).
bool light_sampled(const Material& m) { return m.emits() && !m.cuts_out() && !m.unlit; }

// Whether no ray passes a sphere of this material: its BSDF transmits nothing (glass,
// rough glass, glTF transmission do: bsdfs::transmits), no alpha test's holes, and no
// emission (an emitter is a light of its own, which BSDF sampling must be free to find past
// the cut). A one-sided back absorbs all but camera rays, so it stays opaque; hiding from
// the camera (or culling a back for it) lets only camera rays through, and those take no
// light sample before their first hit.
bool opaque(const Material& m) { return !m.emits() && !m.cuts_out() && !bsdfs::transmits(m); }

}  // namespace

void Scene::check_texture_ids(const Material& material) const {
    const std::pair<const char*, std::int32_t> ids[] = {
        {"albedo_texture", material.albedo_texture},
        {"base_color_texture", material.base_color_texture.texture},
        {"metallic_roughness_texture", material.metallic_roughness_texture.texture},
        {"emission_texture", material.emission_texture.texture},
        {"normal_texture", material.normal_texture.texture},
        {"anisotropy_texture", material.anisotropy_texture.texture},
        {"clearcoat_texture", material.clearcoat_texture.texture},
        {"clearcoat_roughness_texture", material.clearcoat_roughness_texture.texture},
        {"clearcoat_normal_texture", material.clearcoat_normal_texture.texture},
        {"sheen_color_texture", material.sheen_color_texture.texture},
        {"sheen_roughness_texture", material.sheen_roughness_texture.texture},
        {"specular_texture", material.specular_texture.texture},
        {"specular_color_texture", material.specular_color_texture.texture},
        {"transmission_texture", material.transmission_texture.texture},
        {"occlusion_texture", material.occlusion_texture.texture}};
    for (const auto& [name, id] : ids) {
        if (id >= 0 && std::size_t(id) >= textures_.size()) {
            std::ostringstream msg;
            msg << "material " << name << " = " << id << ": only " << textures_.size()
                << " textures in the scene";
            throw Error(msg.str());
        }
    }
}

std::uint32_t Scene::add_material(const Material& material) {
    validate(material);
    check_texture_ids(material);
    materials_.push_back(material);
    cut_outs_ = cut_outs_ || material.cuts_out();
    one_sided_ = one_sided_ || !material.double_sided;
    return std::uint32_t(materials_.size() - 1);
}

std::int32_t Scene::add_texture(ImageTexture texture) {
    if (texture.empty()) throw Error("add_texture: the texture is empty");
    textures_.push_back(std::move(texture));
    return std::int32_t(textures_.size() - 1);
}

void Scene::check_material_id(std::uint32_t material) const {
    if (material >= materials_.size()) {
        std::ostringstream msg;
        msg << "material id " << material << ": the scene has " << materials_.size()
            << " materials";
        throw Error(msg.str());
    }
}

std::uint32_t Scene::add_object(std::uint32_t top_id, std::uint32_t material) {
    committed_ = false;
    // Every object is added to top_ and here in the same order, so the ids agree.
    assert(top_id == objects_.size());
    (void)top_id;
    const bool plain = material != kInvalidId && !materials_[material].varies_per_hit();
    objects_.push_back({kInvalidId, material, plain ? material : kInvalidId});
    return std::uint32_t(objects_.size() - 1);
}

std::uint32_t Scene::add_mesh_object(TriangleMesh mesh, BvhBuilder builder, std::uint32_t material,
                                     std::vector<std::uint32_t> per_triangle) {
    // A normal map or an anisotropic material needs the surface's tangent frame (the glTF
    // loader's rule): a mesh with uvs but no tangents gets them from its uvs (v up, as
    // add_mesh's callers give them).
    const auto needs = [&](std::uint32_t i) { return materials_[i].needs_tangent_frame(); };
    const std::uint32_t prototype = top_.add_prototype(std::move(mesh), builder);
    if (material != kInvalidId ? needs(material)
                               : std::any_of(per_triangle.begin(), per_triangle.end(), needs))
        top_.generate_prototype_tangents(prototype, false);
    const std::uint32_t id = add_object(top_.add_mesh(prototype), material);
    // Vertex colors are a per-hit input: shade() evaluates them out of line.
    if (top_.has_colors(id)) objects_[id].plain_material = kInvalidId;
    if (material == kInvalidId) {
        objects_[id].index = std::uint32_t(triangle_materials_.size());
        triangle_materials_.push_back(std::move(per_triangle));
    }
    return id;
}

std::uint32_t Scene::add_sphere(const Sphere& sphere, std::uint32_t material) {
    check_material_id(material);
    // A sphere's uv costs two inverse trigonometric calls: for intersect_for_shading, only
    // spheres with a texture need it (materials never change once added).
    return add_object(top_.add_sphere(sphere, needs_uv(materials_[material])), material);
}

std::uint32_t Scene::add_sphere(const glm::dvec3& center, double radius, std::uint32_t material) {
    check_material_id(material);
    return add_object(top_.add_sphere(center, radius, needs_uv(materials_[material])), material);
}

std::uint32_t Scene::add_triangle(const Triangle& triangle, std::uint32_t material) {
    check_material_id(material);
    const std::uint32_t id = top_.add_triangle(triangle);
    if (loose_object_ == kInvalidId) {
        loose_object_ = add_object(id, kInvalidId);
        objects_[id].index = std::uint32_t(triangle_materials_.size());
        triangle_materials_.emplace_back();
    }
    committed_ = false;
    triangle_materials_[objects_[loose_object_].index].push_back(material);
    return loose_object_;
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::uint32_t material) {
    return add_mesh(std::move(mesh), material, BvhBuilder::Sah);
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::uint32_t material, BvhBuilder builder) {
    check_material_id(material);
    return add_mesh_object(std::move(mesh), builder, material, {});
}

std::uint32_t Scene::add_mesh_prototype(TriangleMesh mesh, BvhBuilder builder) {
    committed_ = false;
    return top_.add_prototype(std::move(mesh), builder);
}

std::uint32_t Scene::add_instance(std::uint32_t prototype, const glm::mat4& object_to_world,
                                  std::uint32_t material) {
    check_material_id(material);
    const std::uint32_t id = add_object(top_.add_instance(prototype, object_to_world), material);
    if (top_.has_colors(id)) objects_[id].plain_material = kInvalidId;  // see add_mesh_object
    // As in add_mesh_object: a prototype with uvs but no tangents gets them from its uvs
    // when a material placed on it needs a tangent frame. Every instance then shades with
    // the same tangents, whichever was added first.
    if (materials_[material].needs_tangent_frame())
        top_.generate_prototype_tangents(prototype, false);
    return id;
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::vector<std::uint32_t> triangle_materials,
                              BvhBuilder builder) {
    validate(mesh);
    if (triangle_materials.size() != mesh.triangles.size()) {
        throw Error("add_mesh: " + std::to_string(triangle_materials.size()) +
                    " material ids for " + std::to_string(mesh.triangles.size()) + " triangles");
    }
    for (const std::uint32_t m : triangle_materials) check_material_id(m);
    return add_mesh_object(std::move(mesh), builder, kInvalidId, std::move(triangle_materials));
}

std::uint32_t Scene::add_light(Light light) {
    // commit()'s triangle lights go after the added ones: drop them, commit() remakes them.
    lights_.resize(added_lights_);
    lights_.push_back(std::move(light));
    ++added_lights_;
    committed_ = false;
    return std::uint32_t(lights_.size() - 1);
}

void Scene::add_point_light(const PointLight& light) {
    validate(light);
    add_light({light, kInvalidId});
}

std::uint32_t Scene::add_sphere_light(const SphereLight& light) {
    validate(light);
    const std::uint32_t material = add_material(Material::emissive(light.radiance));
    const std::uint32_t object = add_sphere(light.sphere, material);
    if (light_of_object_.size() <= object) light_of_object_.resize(object + 1, kInvalidId);
    light_of_object_[object] = add_light({light, object});
    return object;
}

std::uint32_t Scene::add_surface_light(Light light, TriangleMesh surface,
                                       const glm::vec3& radiance) {
    const std::uint32_t material = add_material(Material::emissive(radiance));
    const std::uint32_t object = add_mesh(std::move(surface), material);
    if (light_of_object_.size() <= object) light_of_object_.resize(object + 1, kInvalidId);
    light.object = object;
    light_of_object_[object] = add_light(std::move(light));
    return object;
}

std::uint32_t Scene::add_quad_light(const QuadLight& light) {
    validate(light);
    TriangleMesh mesh;
    const glm::vec3 c = light.corner, a = c + light.edge0, b = a + light.edge1;
    mesh.positions = {c, a, b, c + light.edge1};
    // (a - c) x (b - c) = edge0 x edge1: both triangles face the light's front.
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    Light l{light, kInvalidId};
    l.one_sided = !light.two_sided;
    return add_surface_light(std::move(l), std::move(mesh), light.radiance);
}

std::uint32_t Scene::add_disk_light(const DiskLight& light) {
    validate(light);
    TriangleMesh mesh;
    mesh.positions.push_back(light.center);
    for (int i = 0; i < kDiskLightSides; ++i) mesh.positions.push_back(disk_light_corner(light, i));
    // Corners run counter-clockwise seen from the front, so each fan triangle faces it.
    for (std::uint32_t i = 0; i < std::uint32_t(kDiskLightSides); ++i)
        mesh.triangles.push_back({0u, 1u + i, 1u + (i + 1) % std::uint32_t(kDiskLightSides)});
    Light l{light, kInvalidId};
    l.one_sided = !light.two_sided;
    return add_surface_light(std::move(l), std::move(mesh), light.radiance);
}

std::uint32_t Scene::add_spot_light(const SpotLight& light) {
    validate(light);
    return add_light({light, kInvalidId});
}

std::uint32_t Scene::add_directional_light(const DirectionalLight& light) {
    validate(light);
    return add_light({light, kInvalidId});
}

std::uint32_t Scene::add_environment_light(const EnvironmentLight& light, bool camera_visible) {
    validate(light);
    Light l{light, kInvalidId};
    l.camera_visible = camera_visible;
    return add_light(std::move(l));
}

void Scene::set_camera_visible(std::uint32_t object_id, bool visible) {
    if (object_id >= objects_.size())
        throw Error("set_camera_visible: object id " + std::to_string(object_id) +
                    ", the scene has " + std::to_string(objects_.size()) + " objects");
    objects_[object_id].camera_visible = visible;
    // Stays set once any object was hidden: a conservative hint (see may_hide_objects).
    if (!visible) hidden_objects_ = true;
}

void Scene::make_triangle_lights() {
    lights_.resize(added_lights_);
    triangle_light_base_.assign(objects_.size(), kInvalidId);
    triangle_light_.clear();
    unsampled_emitters_ = false;
    // Emission textures are shared by the lights through one copy each: the lights are
    // plain values that outlive any reallocation or copy of the scene's textures.
    std::vector<std::shared_ptr<const ImageTexture>> shared(textures_.size());
    // Every emissive triangle that may emit, before keep_triangle_lights chooses among
    // them; triangle_light_ holds indices into it until then.
    std::vector<Light> candidates;
    for (std::uint32_t id = 0; id < objects_.size(); ++id) {
        const Object& o = objects_[id];
        if (light_of_object(id) != kInvalidId) continue;
        auto material_of = [&](std::size_t tri) {
            return o.material != kInvalidId ? o.material : triangle_materials_[o.index][tri];
        };
        const ObjectKind kind = top_.kind(id);
        if (kind == ObjectKind::Sphere) {
            // Spheres that are no sphere light's: their emission is left to BSDF sampling.
            unsampled_emitters_ |= o.material != kInvalidId && materials_[o.material].emits();
            continue;
        }
        // A mesh's triangles as they are; an instance's mapped to the world (the same
        // triangles its hits report, up to rounding), so a placed panel is a light too.
        const bool placed = kind == ObjectKind::Instance;
        const std::pair<glm::mat3, glm::vec3> to_world = top_.object_to_world(id);
        const auto world = [&](const glm::vec3& p) {
            return placed ? to_world.first * p + to_world.second : p;
        };
        const TriangleMesh& mesh = top_.prototype_mesh(top_.prototype_of(id));
        bool any = false;
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const Material& m = materials_[material_of(t)];
            any = any || light_sampled(m);
            unsampled_emitters_ = unsampled_emitters_ || (m.emits() && !light_sampled(m));
        }
        if (!any) continue;
        triangle_light_base_[id] = std::uint32_t(triangle_light_.size());
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const Material& m = materials_[material_of(t)];
            if (!light_sampled(m)) {
                triangle_light_.push_back(kInvalidId);
                continue;
            }
            const glm::uvec3& i = mesh.triangles[t];
            TriangleLight tl;
            tl.p0 = world(mesh.positions[i.x]);
            tl.p1 = world(mesh.positions[i.y]);
            tl.p2 = world(mesh.positions[i.z]);
            tl.radiance = m.emission;
            // Front and back as Scene::shade decides them: by the winding's normal, which
            // a mirroring instance keeps (the world corners' cross product).
            tl.two_sided = m.double_sided;
            if (m.emission_texture.bound()) {
                const auto tex = std::size_t(m.emission_texture.texture);
                if (!shared[tex])
                    shared[tex] = std::make_shared<const ImageTexture>(textures_[tex]);
                tl.texture = shared[tex];
                // Corner uvs as hits interpolate them (barycentrics without uvs; the
                // second set, or (0, 0) without one, for a slot on set 1).
                const auto corner = [&](std::uint32_t v, glm::vec2 bary) {
                    if (m.emission_texture.uv_set == 1)
                        return mesh.uvs1.empty() ? glm::vec2(0.0f) : mesh.uvs1[v];
                    return mesh.uvs.empty() ? bary : mesh.uvs[v];
                };
                tl.uv0 = m.emission_texture.map(corner(i.x, {0.0f, 0.0f}));
                tl.uv1 = m.emission_texture.map(corner(i.y, {1.0f, 0.0f}));
                tl.uv2 = m.emission_texture.map(corner(i.z, {0.0f, 1.0f}));
            }
            // Provably black everywhere (an emission texture black over its whole
            // footprint): no light, and no emitter for BSDF sampling to find either.
            if (emits_nowhere(tl)) {
                triangle_light_.push_back(kInvalidId);
                continue;
            }
            if (tl.texture) tl.mean_texture = mean_texture_estimate(tl);
            triangle_light_.push_back(std::uint32_t(candidates.size()));
            candidates.push_back({std::move(tl), kInvalidId, !m.double_sided});
            candidates.back().camera_visible = o.camera_visible;
        }
    }
    keep_triangle_lights(candidates);
}

void Scene::keep_triangle_lights(std::vector<Light>& candidates) {
    // The power each candidate is chosen by (LightSampler's weight, the mean over channels),
    // its mean radiance (power / (pi area sides), a Lambertian emitter's), their mean
    // over the candidates of positive power, and the power-weighted mean radiance.
    std::vector<double> weight(candidates.size()), radiance(candidates.size(), 0.0);
    double total = 0.0, weighted_radiance = 0.0;
    std::size_t emitting = 0;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const glm::vec3 p = power(candidates[i]);
        const double w = (double(p.x) + double(p.y) + double(p.z)) / 3.0;
        weight[i] = std::isfinite(w) && w > 0.0 ? w : 0.0;
        if (!(weight[i] > 0.0)) continue;
        // The area from the light-level API (the variant stays in light/): a triangle
        // light's sample_le draws its origin uniformly by area, density 1 / A.
        const float per_area = pdf_le(candidates[i], SceneSphere{}, glm::vec3(0.0f),
                                      glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.0f, 1.0f))
                                   .pos;
        const double sides = candidates[i].one_sided ? 1.0 : 2.0;
        radiance[i] = double(per_area) * weight[i] / (kPi * sides);
        total += weight[i];
        weighted_radiance += weight[i] * radiance[i];
        ++emitting;
    }
    // Below either cut-off a candidate is left to BSDF sampling.
    const TriangleLightSettings& s = triangle_light_settings_;
    const double power_cutoff =
        emitting > 0 ? double(s.negligible_power) * total / double(emitting) : 0.0;
    const double radiance_cutoff =
        total > 0.0 ? double(s.negligible_radiance) * weighted_radiance / total : 0.0;
    std::vector<std::uint32_t> index(candidates.size(), kInvalidId);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (!(weight[i] > 0.0) || weight[i] < power_cutoff || radiance[i] < radiance_cutoff) {
            unsampled_emitters_ = true;
            continue;
        }
        index[i] = std::uint32_t(lights_.size());
        lights_.push_back(std::move(candidates[i]));
    }
    for (std::uint32_t& l : triangle_light_)
        if (l != kInvalidId) l = index[l];
}

void Scene::set_triangle_light_settings(const TriangleLightSettings& settings) {
    const auto check = [](float f, const char* name) {
        if (!(f >= 0.0f && f <= 1.0f))
            throw Error(std::string("TriangleLightSettings::") + name + " = " + std::to_string(f) +
                        ": must be in [0, 1]");
    };
    check(settings.negligible_power, "negligible_power");
    check(settings.negligible_radiance, "negligible_radiance");
    triangle_light_settings_ = settings;
    committed_ = false;
}

SceneSphere Scene::bounding_sphere() const {
    const BBox b = top_.bounds();
    if (b.empty()) return {glm::vec3(0.0f), 1.0f};
    return {b.center(), 0.5f * glm::length(b.hi - b.lo)};
}

void Scene::preprocess_lights() {
    // Only top-level analytic spheres of an opaque material that are no light's may bury
    // a sphere light.
    std::vector<DoubleSphere> opaque_spheres;
    for (std::uint32_t id = 0; id < objects_.size(); ++id) {
        if (light_of_object(id) != kInvalidId || top_.kind(id) != ObjectKind::Sphere) continue;
        const std::uint32_t m = objects_[id].material;
        if (m == kInvalidId || !opaque(materials_[m])) continue;
        opaque_spheres.push_back(top_.sphere_geometry(id));
    }
    // Lights at infinity need the scene's size for their power (what the sampler weighs).
    const SceneSummary summary{bounding_sphere(), opaque_spheres};
    infinite_lights_.clear();
    for (std::uint32_t i = 0; i < lights_.size(); ++i) {
        preprocess(lights_[i], summary);
        if (is_infinite(lights_[i])) infinite_lights_.push_back(i);
    }
}

void Scene::commit() {
    if (committed_) return;
    try {
        top_.build();
        make_triangle_lights();
        preprocess_lights();
        light_sampler_ = LightSampler(lights_);
    } catch (const std::bad_alloc&) {
        // A scene that loaded within its bounds may still not fit the machine: an Error
        // the apps report, never bad_alloc. The scene stays uncommitted.
        throw Error(
            "Scene::commit: out of memory while building the acceleration structures "
            "and lights (allocation failed)");
    }
    pass_through_surfaces_ = std::any_of(materials_.begin(), materials_.end(),
                                         [](const Material& m) { return may_pass_through(m); });
    careful_queries_ = cut_outs_ || pass_through_surfaces_;
    committed_ = true;
}

void Scene::throw_not_committed() {
    throw Error("Scene queried before commit(): call commit() after adding objects");
}

std::uint32_t Scene::material_id(const Hit& hit) const {
    const Object& o = objects_[hit.object_id];
    if (o.material != kInvalidId) return o.material;
    return triangle_materials_[o.index][hit.primitive_id];
}

glm::vec3 Scene::albedo(const Hit& hit) const {
    const Material& m = material(hit);
    if (m.albedo_texture >= 0) return textures_[std::size_t(m.albedo_texture)].lookup(hit.uv);
    return m.albedo;
}

}  // namespace librt
