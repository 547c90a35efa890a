#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/io/texture_io.h>
#include <librt/obj/obj_materials.h>

#include <cstdio>
#include <string>
#include <utility>

namespace librt {
namespace {

bool any_positive(const glm::vec3& v) { return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f; }

/// "scene.mtl:3: MTL material 'red'": where the material was defined, as the OBJ loader's
/// messages start, and its name quoted as text from a file (escaped and capped).
std::string material_text(const MeshMaterial& mtl) {
    std::string out = mtl.defined_at.empty() ? std::string() : mtl.defined_at + ": ";
    out += "MTL material ";
    out += quote_untrusted(mtl.name);
    return out;
}

}  // namespace

Material material_from_mtl(const MeshMaterial& mtl) {
    try {
        if (any_positive(mtl.emission)) return Material::emissive(mtl.emission);
        if (mtl.illum == 4 || mtl.illum == 6 || mtl.illum == 7 || mtl.dissolve < 1.0f)
            return Material::dielectric(mtl.ior > 0.0f ? mtl.ior : 1.5f);
        if (mtl.illum == 3 || mtl.illum == 5 || mtl.specular == glm::vec3(1.0f)) {
            // A mirror's reflectance is the MTL's Ks: say so, not the Material's "albedo".
            const glm::vec3 ks = any_positive(mtl.specular) ? mtl.specular : glm::vec3(1.0f);
            for (int c = 0; c < 3; ++c) {
                if (!(ks[c] >= 0.0f && ks[c] <= 1.0f)) {
                    char text[96];
                    std::snprintf(text, sizeof text, "(%g, %g, %g)", double(ks.x), double(ks.y),
                                  double(ks.z));
                    throw Error(std::string("Ks = ") + text +
                                ": a mirror's reflectance, every component must be in [0, 1]");
                }
            }
            return Material::mirror(ks);
        }
        return Material::diffuse(mtl.diffuse);
    } catch (const Error& e) {
        throw Error(material_text(mtl) + ": " + e.what());
    }
}

MtlMeshResult add_mesh_with_mtl(Scene& scene, TriangleMesh mesh, std::uint32_t fallback_material,
                                TextureIdsByPath* textures) {
    if (fallback_material >= scene.material_count()) {
        throw Error("material id " + std::to_string(fallback_material) + ": the scene has " +
                    std::to_string(scene.material_count()) + " materials");
    }
    validate(mesh);
    MtlMeshResult result;
    std::vector<std::uint32_t> per_triangle(mesh.triangles.size(), fallback_material);
    if (!mesh.material_ids.empty()) {
        TextureIdsByPath local;
        TextureIdsByPath& loaded = textures ? *textures : local;
        std::vector<std::uint32_t> mapped(mesh.materials.size());
        for (std::size_t i = 0; i < mesh.materials.size(); ++i) {
            const MeshMaterial& mtl = mesh.materials[i];
            Material m = material_from_mtl(mtl);
            if (m.kind == MaterialKind::Diffuse && !mtl.diffuse_texture.empty()) {
                const auto [it, added] = loaded.try_emplace(mtl.diffuse_texture, -1);
                if (added) {
                    try {
                        FileDigest digest;
                        it->second = scene.add_texture(load_texture(mtl.diffuse_texture, &digest));
                        result.files_read.push_back({mtl.diffuse_texture, digest});
                    } catch (const Error& e) {
                        // e.what() names the image file and is printable already.
                        result.warnings.push_back(material_text(mtl) + ": " + e.what() +
                                                  "; using its Kd instead");
                    }
                }
                m.albedo_texture = it->second;
            }
            mapped[i] = scene.add_material(m);
        }
        for (std::size_t i = 0; i < per_triangle.size(); ++i)
            per_triangle[i] = mapped[mesh.material_ids[i]];  // in range: validated
    }
    result.object_id = scene.add_mesh(std::move(mesh), std::move(per_triangle));
    return result;
}

}  // namespace librt
