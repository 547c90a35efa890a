#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/film/framing.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/io/file_extension.h>
#include <librt/loader/scene_file.h>
#include <librt/obj/obj.h>
#include <librt/obj/obj_materials.h>
#include <librt/scene/default_lighting.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <new>
#include <string>
#include <utility>

namespace librt {

CameraSettings view_camera(const CameraSettings& camera, bool framed, const BBox& bounds,
                           const ViewOptions& view, std::string& camera_name) {
    if (view.empty()) return camera;
    try {
        CameraSettings c = apply_view(camera, framed, bounds, view);
        if (view.orbit_degrees) camera_name = "default";
        return c;
    } catch (const Error& e) {
        throw Error(std::string("view: ") + e.what());
    }
}

CameraSettings default_camera(const BBox& bounds, int width, int height) {
    try {
        return frame_bounds(bounds, width, height);
    } catch (const Error& e) {
        throw Error(std::string("default_camera: ") + e.what());
    }
}

LoadedScene scene_from_obj(const std::filesystem::path& path, const SceneFileOptions& options) {
    // Refused before the file is read, as a glTF with too few scenes or no such variant is.
    if (options.scene > 0)
        throw Error(path.string() + ": scene " + std::to_string(options.scene) +
                    " requested, an OBJ file has one (scene 0)");
    if (!options.variant.empty())
        throw Error(path.string() + ": variant " + quote_untrusted(options.variant) +
                    ": an OBJ file has no material variants (KHR_materials_variants is glTF's)");
    LoadedScene out;
    ObjLoadOptions obj;
    obj.warnings = &out.warnings;
    obj.files_read = &out.files_read;
    obj.allow_outside_files = options.allow_outside_files;
    TriangleMesh mesh = load_obj(path, obj);
    if (mesh.triangle_count() == 0) throw Error(path.string() + ": no triangles to render");
    out.bounds = mesh.bounds();
    out.triangles_stored = out.triangles_placed = mesh.triangle_count();
    const bool emits =
        std::any_of(mesh.materials.begin(), mesh.materials.end(), [](const MeshMaterial& m) {
            return m.emission.x > 0.0f || m.emission.y > 0.0f || m.emission.z > 0.0f;
        });
    const std::uint32_t fallback = out.scene.add_material(Material::diffuse(glm::vec3(0.8f)));
    MtlMeshResult added = add_mesh_with_mtl(out.scene, std::move(mesh), fallback);
    for (std::string& w : added.warnings) out.warnings.push_back(std::move(w));
    for (FileRead& f : added.files_read) out.files_read.push_back(std::move(f));
    if (!options.camera.empty() && options.camera != "auto") {
        out.warnings.push_back("camera = " + options.camera +
                               ": an OBJ has no cameras, using the default");
    }
    const int side = std::max(1, options.default_long_side);
    const bool sized = options.width > 0 && options.height > 0;
    out.camera = default_camera(out.bounds, sized ? options.width : side,
                                sized ? options.height : std::max(1, side * 3 / 4));
    out.camera_name = "default";
    out.camera = view_camera(out.camera, true, out.bounds, options.view, out.camera_name);
    if (!emits && options.default_lighting)
        out.lighting_note = add_studio_lighting(out.scene, out.camera, options.background_visible);
    return out;
}

namespace {

/// A .gltf or .glb file as a scene: load_gltf, then scene_from_gltf with the file named in
/// each of its messages.
LoadedScene scene_from_gltf_file(const std::filesystem::path& path,
                                 const SceneFileOptions& options) {
    GltfLoadOptions load_options;
    load_options.allow_outside_files = options.allow_outside_files;
    load_options.scene = options.scene;
    load_options.variant = options.variant;
    // Its errors and warnings name the file already.
    GltfScene gltf = load_gltf(path, load_options);
    const std::size_t named = gltf.warnings.size();
    // scene_from_gltf's messages give the JSON path (it does not know the file): the
    // file is prefixed here, so that every message says "file: JSON path: what".
    const std::string file = path.string() + ": ";
    try {
        LoadedScene out = scene_from_gltf(std::move(gltf), options);
        for (std::size_t i = named; i < out.warnings.size(); ++i)
            out.warnings[i] = printable(file + out.warnings[i], kMaxErrorBytes);
        return out;
    } catch (const Error& e) {
        throw Error(file + e.what());
    }
}

/// "a, b or c" of the known extensions, for the unknown-format error.
std::string known_extensions() {
    std::vector<std::string> all;
    for (const SceneFileFormat& f : scene_file_formats())
        all.insert(all.end(), f.extensions.begin(), f.extensions.end());
    std::string out;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (i > 0) out += i + 1 == all.size() ? " or " : ", ";
        out += all[i];
    }
    return out;
}

}  // namespace

const std::vector<SceneFileFormat>& scene_file_formats() {
    // The registrations: a new format is one row here (and its loader).
    static const std::vector<SceneFileFormat> formats{
        {"glTF 2.0", {".gltf", ".glb"}, &scene_from_gltf_file},
        {"Wavefront OBJ with MTL materials", {".obj"}, &scene_from_obj},
    };
    return formats;
}

LoadedScene load_scene_file(const std::filesystem::path& path, const SceneFileOptions& options) {
    const std::string ext = lower_extension(path);
    for (const SceneFileFormat& format : scene_file_formats()) {
        if (std::find(format.extensions.begin(), format.extensions.end(), ext) ==
            format.extensions.end())
            continue;
        try {
            return format.load(path, options);
        } catch (const std::bad_alloc&) {
            // The one place for every format: a load under a memory limit (the size limits
            // passed, the machine had less) is an Error naming the file, never bad_alloc.
            throw Error(path.string() + ": out of memory while loading (allocation failed)");
        }
    }
    throw Error(path.string() + ": unknown scene format '" + ext + "' (expected " +
                known_extensions() + ")");
}

}  // namespace librt
