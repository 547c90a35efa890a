#pragma once

#include <librt/export.h>
#include <librt/io/loaded_scene.h>

#include <filesystem>
#include <string>
#include <vector>

// One entry point for "render this file": glTF (.gltf, .glb) through gltf/gltf_scene.h, or a
// Wavefront OBJ with its MTL materials as a whole scene.

namespace librt {

/// An OBJ (and its MTL) as a scene: one mesh with its MTL materials (obj/obj_materials.h
/// add_mesh_with_mtl; faces without a material are diffuse 0.8), default_camera() framing
/// it and, unless some MTL material emits or options.default_lighting is false,
/// add_studio_lighting (scene/default_lighting.h). Throws librt::Error from
/// load_obj, or for a mesh with no triangles.
[[nodiscard]] LIBRT_API LoadedScene scene_from_obj(const std::filesystem::path& path,
                                                   const SceneFileOptions& options = {});

/// A scene file format load_scene_file knows: its name, its extensions (lower case, with
/// the dot) and the function that turns such a file into a scene.
struct SceneFileFormat {
    std::string name;                     ///< what it is called, e.g. "glTF 2.0"
    std::vector<std::string> extensions;  ///< lower case, with the dot: ".gltf", ".glb"
    /// Loads such a file; throws librt::Error naming the path.
    LoadedScene (*load)(const std::filesystem::path& path, const SceneFileOptions& options);
};

/// Every format load_scene_file knows, in the order of its "expected ..." message: the one
/// registration of a new format (src/loader/scene_file.cpp; docs/architecture.md, "Adding a
/// scene format").
[[nodiscard]] LIBRT_API const std::vector<SceneFileFormat>& scene_file_formats();

/// Loads a scene file chosen by extension (case-insensitive) from scene_file_formats():
/// .obj through scene_from_obj, .gltf and .glb through load_gltf and scene_from_gltf.
/// Throws librt::Error naming the path and every known extension for any other extension,
/// and the loaders' errors; running out of memory in any loader is the Error "path: out of
/// memory while loading (allocation failed)", never std::bad_alloc. Every glTF error and warning
/// reads "path: JSON path: what": scene_from_gltf's (which knows the JSON path, not the file) get
/// the path prefixed here.
[[nodiscard]] LIBRT_API LoadedScene load_scene_file(const std::filesystem::path& path,
                                                    const SceneFileOptions& options = {});

}  // namespace librt
