#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/core/error.h>
#include <librt/render/scene.h>

#include <cmath>
#include <iostream>
#include <sstream>

namespace librt {
namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Checks what queries rely on: indices in range, optional arrays of the right length,
// finite positions. (librt::validate(TriangleMesh) says more once it is available.)
void check_mesh(const TriangleMesh& mesh) {
    const std::size_t n = mesh.positions.size();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const glm::uvec3& t = mesh.triangles[i];
        if (t.x >= n || t.y >= n || t.z >= n) {
            std::ostringstream msg;
            msg << "mesh triangle " << i << " = (" << t.x << ", " << t.y << ", " << t.z
                << "): index out of range (" << n << " positions)";
            throw Error(msg.str());
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!finite(mesh.positions[i])) {
            std::ostringstream msg;
            msg << "mesh position " << i << " is not finite";
            throw Error(msg.str());
        }
    }
    // NaN normals or uvs would reach shading (and the texture lookup) unchecked.
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        if (!finite(mesh.normals[i])) throw Error("mesh normal " + std::to_string(i) + " is not finite");
    }
    for (std::size_t i = 0; i < mesh.uvs.size(); ++i) {
        if (!std::isfinite(mesh.uvs[i].x) || !std::isfinite(mesh.uvs[i].y))
            throw Error("mesh uv " + std::to_string(i) + " is not finite");
    }
    auto check_size = [](const char* what, std::size_t got, std::size_t want) {
        if (got != 0 && got != want) {
            std::ostringstream msg;
            msg << "mesh " << what << " has " << got << " entries, expected 0 or " << want;
            throw Error(msg.str());
        }
    };
    check_size("normals", mesh.normals.size(), n);
    check_size("uvs", mesh.uvs.size(), n);
    check_size("material_ids", mesh.material_ids.size(), mesh.triangles.size());
}

// The unit normal of a triangle from its winding; `fallback` when degenerate.
glm::vec3 unit_or(const glm::vec3& v, const glm::vec3& fallback) {
    const float len2 = glm::dot(v, v);
    if (!(len2 > 0.0f) || !std::isfinite(len2)) return fallback;
    return v / std::sqrt(len2);
}

}  // namespace

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

std::uint32_t Scene::add_object(ObjectKind kind, std::uint32_t index, std::uint32_t material) {
    committed_ = false;
    objects_.push_back({kind, false, index, material});
    return std::uint32_t(objects_.size() - 1);
}

std::uint32_t Scene::add_sphere(const Sphere& sphere, std::uint32_t material) {
    check_material_id(material);
    if (!finite(sphere.center)) {
        std::ostringstream msg;
        msg << "sphere center = (" << sphere.center.x << ", " << sphere.center.y << ", "
            << sphere.center.z << "): must be finite";
        throw Error(msg.str());
    }
    if (!std::isfinite(sphere.radius) || !(sphere.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "sphere radius = " << sphere.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    spheres_.push_back(sphere);
    return add_object(ObjectKind::Sphere, std::uint32_t(spheres_.size() - 1), material);
}

std::uint32_t Scene::add_triangle(const Triangle& triangle, std::uint32_t material) {
    check_material_id(material);
    if (!finite(triangle.p0) || !finite(triangle.p1) || !finite(triangle.p2))
        throw Error("add_triangle: corners must be finite");
    if (loose_object_ == kInvalidId) {
        meshes_.emplace_back();
        loose_object_ = add_object(ObjectKind::Mesh, std::uint32_t(meshes_.size() - 1), kInvalidId);
    }
    committed_ = false;
    MeshData& data = meshes_[objects_[loose_object_].index];
    const auto base = std::uint32_t(data.mesh.positions.size());
    data.mesh.positions.insert(data.mesh.positions.end(), {triangle.p0, triangle.p1, triangle.p2});
    data.mesh.triangles.emplace_back(base, base + 1, base + 2);
    data.triangle_materials.push_back(material);
    return loose_object_;
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::uint32_t material) {
    check_material_id(material);
    check_mesh(mesh);
    meshes_.push_back({std::move(mesh), {}, {}});
    return add_object(ObjectKind::Mesh, std::uint32_t(meshes_.size() - 1), material);
}

std::uint32_t Scene::mtl_to_material(const MeshMaterial& mtl) {
    const auto any_positive = [](const glm::vec3& v) {
        return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f;
    };
    Material m;
    try {
        if (any_positive(mtl.emission)) {
            m = Material::emissive(mtl.emission);
        } else if (mtl.illum == 4 || mtl.illum == 6 || mtl.illum == 7 || mtl.dissolve < 1.0f) {
            m = Material::dielectric(mtl.ior > 0.0f ? mtl.ior : 1.5f);
        } else if (mtl.illum == 3 || mtl.illum == 5 || mtl.specular == glm::vec3(1.0f)) {
            m = Material::mirror(any_positive(mtl.specular) ? mtl.specular : glm::vec3(1.0f));
        } else {
            m = Material::diffuse(mtl.diffuse);
            if (!mtl.diffuse_texture.empty()) {
                const auto it = texture_by_path_.find(mtl.diffuse_texture);
                if (it != texture_by_path_.end()) {
                    m.albedo_texture = it->second;
                } else {
                    try {
                        m.albedo_texture = add_texture(ImageTexture::load(mtl.diffuse_texture));
                        texture_by_path_.emplace(mtl.diffuse_texture, m.albedo_texture);
                    } catch (const Error& e) {
                        std::cerr << "librt: warning: material '" << mtl.name << "': " << e.what()
                                  << "; using its Kd instead\n";
                        texture_by_path_.emplace(mtl.diffuse_texture, -1);
                    }
                }
            }
        }
    } catch (const Error& e) {
        throw Error("MTL material '" + mtl.name + "': " + e.what());
    }
    return add_material(m);
}

std::uint32_t Scene::add_mesh_with_mtl(TriangleMesh mesh, std::uint32_t fallback_material) {
    check_material_id(fallback_material);
    check_mesh(mesh);
    std::vector<std::uint32_t> mapped(mesh.materials.size());
    for (std::size_t i = 0; i < mesh.materials.size(); ++i)
        mapped[i] = mtl_to_material(mesh.materials[i]);
    std::vector<std::uint32_t> per_triangle(mesh.triangles.size(), fallback_material);
    for (std::size_t i = 0; i < mesh.material_ids.size(); ++i) {
        const std::uint32_t id = mesh.material_ids[i];
        if (id < mapped.size()) per_triangle[i] = mapped[id];
    }
    meshes_.push_back({std::move(mesh), {}, std::move(per_triangle)});
    return add_object(ObjectKind::Mesh, std::uint32_t(meshes_.size() - 1), kInvalidId);
}

void Scene::add_point_light(const PointLight& light) {
    validate(light);
    point_lights_.push_back(light);
}

std::uint32_t Scene::add_sphere_light(const SphereLight& light) {
    validate(light);
    const std::uint32_t material = add_material(Material::emissive(light.radiance));
    const std::uint32_t object = add_sphere(light.sphere, material);
    objects_[object].light = true;
    sphere_lights_.push_back(light);
    sphere_light_objects_.push_back(object);
    return object;
}

void Scene::commit() {
    if (committed_) return;
    std::vector<BBox> boxes;
    std::vector<glm::vec3> centers;
    std::vector<std::uint32_t> ids;
    for (std::uint32_t id = 0; id < objects_.size(); ++id) {
        const Object& o = objects_[id];
        BBox box;
        if (o.kind == ObjectKind::Sphere) {
            box = librt::bounds(spheres_[o.index]);
        } else {
            MeshData& m = meshes_[o.index];
            if (m.bvh.triangle_count() != m.mesh.triangle_count() || m.bvh.bvh().empty())
                m.bvh = TriangleBvh(m.mesh, BvhBuilder::Sah);
            box = m.bvh.bounds();
        }
        if (box.empty()) continue;  // an empty mesh can be hit by nothing
        boxes.push_back(box);
        centers.push_back(box.center());
        ids.push_back(id);
    }
    top_ = build_sah_bvh(boxes, centers);
    slot_object_.resize(top_.prim_indices.size());
    for (std::size_t slot = 0; slot < slot_object_.size(); ++slot)
        slot_object_[slot] = ids[top_.prim_indices[slot]];
    committed_ = true;
}

void Scene::require_committed() const {
    if (!committed_) throw Error("Scene queried before commit(): call commit() after adding objects");
}

bool Scene::intersect(const Ray& ray, Hit& hit) const {
    require_committed();
    Ray r = ray;
    std::uint32_t best_object = kInvalidId;
    PrimitiveHit best;
    traverse<false>(top_, r, [&](std::uint32_t slot, Ray& current) {
        const std::uint32_t id = slot_object_[slot];
        const Object& o = objects_[id];
        if (o.kind == ObjectKind::Sphere) {
            const auto t = librt::intersect(spheres_[o.index], current);
            if (!t) return false;
            current.t_max = *t;
            best = {*t, 0.0f, 0.0f, 0};
        } else {
            const PrimitiveHit h = meshes_[o.index].bvh.intersect(current);
            if (!h.valid()) return false;
            current.t_max = h.t;
            best = h;
        }
        best_object = id;
        return true;
    });
    if (best_object == kInvalidId) return false;
    finish_hit(ray, best_object, best, hit);
    return true;
}

bool Scene::occluded(const Ray& ray, std::uint32_t ignored_object) const {
    require_committed();
    Ray r = ray;
    return traverse<true>(top_, r, [&](std::uint32_t slot, Ray& current) {
        const std::uint32_t id = slot_object_[slot];
        if (id == ignored_object) return false;
        const Object& o = objects_[id];
        if (o.kind == ObjectKind::Sphere)
            return librt::intersect(spheres_[o.index], current).has_value();
        return meshes_[o.index].bvh.occluded(current);
    });
}

void Scene::finish_hit(const Ray& ray, std::uint32_t object_id, const PrimitiveHit& prim,
                       Hit& hit) const {
    const Object& o = objects_[object_id];
    hit.t = prim.t;
    hit.object_id = object_id;
    const glm::vec3 back = -ray.direction;  // fallback orientation for degenerate normals
    if (o.kind == ObjectKind::Sphere) {
        const Sphere& s = spheres_[o.index];
        hit.point = ray.at(prim.t);
        hit.geometric_normal = unit_or(hit.point - s.center, back);
        hit.shading_normal = hit.geometric_normal;
        // v flipped so that it grows toward +y like OBJ coordinates: images map upright.
        const glm::vec2 uv = sphere_uv(s, hit.point);
        hit.uv = {uv.x, 1.0f - uv.y};
        hit.primitive_id = 0;
        return;
    }
    const TriangleMesh& mesh = meshes_[o.index].mesh;
    const glm::uvec3& idx = mesh.triangles[prim.primitive_id];
    const float b1 = prim.u, b2 = prim.v, b0 = 1.0f - prim.u - prim.v;
    const glm::vec3& p0 = mesh.positions[idx.x];
    const glm::vec3& p1 = mesh.positions[idx.y];
    const glm::vec3& p2 = mesh.positions[idx.z];
    // Barycentric interpolation lands closer to the plane than o + t d does.
    hit.point = b0 * p0 + b1 * p1 + b2 * p2;
    hit.geometric_normal = unit_or(glm::cross(p1 - p0, p2 - p0), back);
    hit.shading_normal = hit.geometric_normal;
    if (!mesh.normals.empty()) {
        const glm::vec3 n =
            b0 * mesh.normals[idx.x] + b1 * mesh.normals[idx.y] + b2 * mesh.normals[idx.z];
        const glm::vec3 ns = unit_or(n, hit.geometric_normal);
        hit.shading_normal = glm::dot(ns, hit.geometric_normal) < 0.0f ? -ns : ns;
    }
    hit.uv = mesh.uvs.empty()
                 ? glm::vec2(b1, b2)
                 : b0 * mesh.uvs[idx.x] + b1 * mesh.uvs[idx.y] + b2 * mesh.uvs[idx.z];
    hit.primitive_id = prim.primitive_id;
}

std::uint32_t Scene::material_id(const Hit& hit) const {
    const Object& o = objects_[hit.object_id];
    if (o.material != kInvalidId) return o.material;
    return meshes_[o.index].triangle_materials[hit.primitive_id];
}

glm::vec3 Scene::albedo(const Hit& hit) const {
    const Material& m = material(hit);
    if (m.albedo_texture >= 0) return textures_[std::size_t(m.albedo_texture)].lookup(hit.uv);
    return m.albedo;
}

}  // namespace librt
