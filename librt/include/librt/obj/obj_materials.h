#pragma once

#include <librt/export.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/io/file_digest.h>
#include <librt/material/material.h>
#include <librt/scene/scene.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace librt {

/// The scene material an MTL material stands for, texture aside: Ke != 0 -> emissive Ke;
/// illum 4, 6, 7 or d < 1 -> dielectric of index Ni (1.5 when Ni is not > 0); illum 3, 5 or
/// Ks = 1 -> mirror tinted by Ks (white when Ks is 0); otherwise diffuse Kd. Reads no file:
/// map_Kd is left to add_mesh_with_mtl. Throws librt::Error "MTL material 'name': ..." for a
/// value no Material accepts (e.g. Kd above 1).
[[nodiscard]] LIBRT_API Material material_from_mtl(const MeshMaterial& mtl);

/// Scene texture ids of the texture files already loaded into one scene, by map_Kd path as
/// the mesh gives it; -1 for a file that failed to load (it is not tried again).
using TextureIdsByPath = std::map<std::string, std::int32_t>;

/// What add_mesh_with_mtl added, and what it had to leave out.
struct MtlMeshResult {
    std::uint32_t object_id = kInvalidId;  ///< the mesh's object id in the scene
    /// One line per texture file that could not be loaded, naming the MTL material and the
    /// file with the reason; such a material keeps its Kd. The library prints nothing:
    /// the caller shows these as it sees fit.
    std::vector<std::string> warnings;
    /// The texture files this call loaded, each once, with the digest of their bytes (by
    /// the map_Kd path the mesh gives); one that failed (a warning above) is not listed, nor
    /// is one already in `textures` (not read again).
    std::vector<FileRead> files_read;
};

/// Adds `mesh` to `scene` with its MTL materials: each of mesh.materials becomes a new
/// scene material (material_from_mtl) and, when diffuse with a map_Kd,
/// gets that image (io/texture_io.h load_texture) as albedo texture, each file loaded once
/// (once per scene when the same `textures` is passed to every call; once per call when it
/// is null). A mesh without material_ids uses `fallback_material` throughout and adds no
/// material. Then Scene::add_mesh with per-triangle material ids. Throws librt::Error,
/// before adding anything, for an unknown fallback id or an invalid mesh (librt::validate:
/// e.g. a material id out of range), and for an MTL value no Material accepts (naming the
/// material; the materials mapped before it stay in the scene, unused).
[[nodiscard]] LIBRT_API MtlMeshResult add_mesh_with_mtl(Scene& scene, TriangleMesh mesh,
                                                        std::uint32_t fallback_material,
                                                        TextureIdsByPath* textures = nullptr);

}  // namespace librt
