#pragma once

// scene_from_gltf's materials and textures: glTF materials to librt MetallicRoughness
// materials, their textures to scene textures (once per image, sampler and colour space),
// and the uv set and tangents a primitive's mesh needs for them; and named(), how
// scene_from_gltf's messages give a name from the file. Private to io/.

#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/scene/scene.h>

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace librt::gltf_detail {

/// "nodes[4] 'name'": a JSON path and the name the file gives that object, quoted by
/// quote_untrusted (escaped and capped: a name may hold escape sequences, CR/LF or
/// megabytes). The one way scene_from_gltf's messages show a name; the data structures
/// keep the names as they are.
[[nodiscard]] std::string named(std::string_view json_path, std::string_view name);

/// What a scene material needs from the meshes that use it.
struct SceneMaterial {
    std::uint32_t id = 0;         ///< scene material id
    int uv_set = -1;              ///< TEXCOORD_n its first texture reads; -1 when it has none
    bool second_set = false;      ///< another texture reads the other TEXCOORD_n (mesh uvs1)
    bool needs_tangents = false;  ///< a normal map or anisotropy: needs tangents
    bool textured = false;        ///< some texture reads uv_set (else only tangents need it)
};

/// Adds the materials and textures of a GltfScene to a Scene on first use.
class MaterialBuilder {
public:
    MaterialBuilder(const GltfScene& gltf, Scene& scene, std::vector<std::string>& warnings,
                    const GltfMaterialChoices& choices = {});
    /// The scene material of glTF material `index` (-1 or out of range: the default).
    const SceneMaterial& material(int index);
    /// True when some material built so far emits.
    [[nodiscard]] bool emissive() const { return emissive_; }
    /// Puts the uvs and tangents `m` needs into `mesh` from `prim` (uvs as glTF states
    /// them: v down; tangents given, else generated), warning when they are missing.
    void attributes(const GltfPrimitive& prim, const SceneMaterial& m, TriangleMesh& mesh,
                    const std::string& who);

private:
    std::int32_t texture(const GltfTextureRef& ref, ColorSpace space);
    /// The hints and warnings about a material's transmission and volume (thin-walled or
    /// solid, what solid glass leaves out).
    void transmission_notes(const GltfMaterial& m, const std::string& who);

    const GltfScene& gltf_;
    Scene& scene_;
    std::vector<std::string>& warnings_;
    std::vector<SceneMaterial> built_;  ///< per glTF material; id 0 = not built yet
    std::vector<bool> done_;
    SceneMaterial default_;
    std::map<std::pair<int, ColorSpace>, std::int32_t> textures_;
    bool emissive_ = false;
    GltfMaterialChoices choices_;
};

}  // namespace librt::gltf_detail
