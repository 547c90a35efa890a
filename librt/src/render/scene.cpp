#include <librt/core/error.h>
#include <librt/render/scene.h>

#include <sstream>

namespace librt {

std::uint32_t Scene::add_material(const Material& material) {
    validate(material);
    if (material.albedo_texture >= 0 && std::size_t(material.albedo_texture) >= textures_.size()) {
        std::ostringstream msg;
        msg << "material albedo_texture = " << material.albedo_texture << ": only "
            << textures_.size() << " textures in the scene";
        throw Error(msg.str());
    }
    materials_.push_back(material);
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
    objects_.push_back({kInvalidId, material});
    return std::uint32_t(objects_.size() - 1);
}

std::uint32_t Scene::add_mesh_object(TriangleMesh mesh, BvhBuilder builder, std::uint32_t material,
                                     std::vector<std::uint32_t> per_triangle) {
    const std::uint32_t prototype = top_.add_prototype(std::move(mesh), builder);
    const std::uint32_t id = add_object(top_.add_mesh(prototype), material);
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
    return add_object(top_.add_sphere(sphere, materials_[material].albedo_texture >= 0), material);
}

std::uint32_t Scene::add_sphere(const glm::dvec3& center, double radius, std::uint32_t material) {
    check_material_id(material);
    return add_object(top_.add_sphere(center, radius, materials_[material].albedo_texture >= 0),
                      material);
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
    return add_object(top_.add_instance(prototype, object_to_world), material);
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

void Scene::add_point_light(const PointLight& light) {
    validate(light);
    lights_.push_back({light, kInvalidId});
    committed_ = false;
}

std::uint32_t Scene::add_sphere_light(const SphereLight& light) {
    validate(light);
    const std::uint32_t material = add_material(Material::emissive(light.radiance));
    const std::uint32_t object = add_sphere(light.sphere, material);
    if (light_of_object_.size() <= object) light_of_object_.resize(object + 1, kInvalidId);
    light_of_object_[object] = std::uint32_t(lights_.size());
    lights_.push_back({light, object});
    return object;
}

void Scene::commit() {
    if (committed_) return;
    top_.build();
    unsampled_emitters_ = false;
    for (std::uint32_t id = 0; id < objects_.size(); ++id) {
        const Object& o = objects_[id];
        if (light_of_object(id) != kInvalidId) continue;
        if (o.material != kInvalidId) {
            unsampled_emitters_ |= materials_[o.material].emits();
        } else {
            for (const std::uint32_t m : triangle_materials_[o.index])
                unsampled_emitters_ |= materials_[m].emits();
        }
    }
    light_sampler_ = LightSampler(lights_);
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
