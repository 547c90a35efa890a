#pragma once

#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/film/framing.h>
#include <librt/geometry/bbox.h>
#include <librt/io/file_digest.h>
#include <librt/scene/scene.h>

#include <cstddef>
#include <string>
#include <vector>

// What a scene file (glTF or OBJ) becomes: a Scene ready to commit, the camera to render
// it through, and what had to be left out. gltf/gltf_scene.h and loader/scene_file.h fill it.

namespace librt {

/// What the numbers of a glTF file's punctual lights (KHR_lights_punctual: candela for point
/// and spot lights, lux for directional ones) become in librt's radiometric units (W/sr,
/// W/m^2). docs/render-your-own-scene.md, "Light units", says which exporters need which.
enum class PunctualLightUnits {
    /// Divided by 683 lm/W (the luminous efficacy of 555 nm light): the inverse of Blender's
    /// exporter, which writes a P W point light as P * 683 / (4 pi) cd and a sun of E W/m^2
    /// as 683 E lux, so that its lights come back as Blender rendered them.
    Watts,
    /// Taken as they are, 1 cd as 1 W/sr and 1 lux as 1 W/m^2: the scale of web viewers
    /// (three.js, the Khronos glTF Sample Viewer) that light with the numbers as they are at
    /// exposure 1. Files authored for such viewers (a 3 lux sun) need it.
    Photometric,
};

/// How a scene file is turned into a Scene and a camera.
struct SceneFileOptions {
    /// The file's camera to use (perspective or orthographic): empty = the first; all digits = the
    /// index among the cameras the scene places (node order); "auto" = default_camera()
    /// even when the file has cameras (a camera named "auto" is reached by its index);
    /// else a camera (or its node's) name. A file without cameras gets default_camera().
    std::string camera;
    int width = 0;   ///< image width; 0 (with height 0) = from the camera's aspect ratio
    int height = 0;  ///< image height; 0 (with width 0) = from the camera's aspect ratio
    /// Longest image side when the size follows the camera's aspect ratio.
    int default_long_side = 640;
    /// Let the scene read files outside its own directory tree (GltfLoadOptions and
    /// ObjLoadOptions::allow_outside_files): only for a file you trust.
    bool allow_outside_files = false;
    /// A file without lights of its own gets add_studio_lighting (scene/default_lighting.h)
    /// for the chosen camera, noted in LoadedScene::lighting_note. "Without lights": a glTF
    /// with no punctual light (KHR_lights_punctual) that loads, emissive surfaces or not; an
    /// OBJ with no emissive MTL material (MTL has no other light: an emitter is the
    /// author's lighting). false: the file's own lights alone.
    bool default_lighting = true;
    /// Whether camera rays that leave the scene see the default lighting's sky; false keeps
    /// its light on the model but a black background behind it (a transparent background).
    bool background_visible = true;
    /// A viewpoint replacing the chosen camera's (film/framing.h, apply_view), applied
    /// before the default lighting is placed for it; its errors are prefixed "view: ".
    ViewOptions view;
    /// glTF: which of the file's scenes (its "scenes" array) to load; -1 = the file's default
    /// ("scene", else 0). An index the file does not have is an error naming the count. An
    /// OBJ is one scene: only -1 and 0 are accepted.
    int scene = -1;
    /// glTF: the KHR_materials_variants variant to show, by name; empty = the primitives' own
    /// materials. A name the file does not define is an error listing the names it does.
    /// An OBJ has no variants: any name is an error.
    std::string variant;
    /// glTF: the units of KHR_lights_punctual intensities (PunctualLightUnits).
    PunctualLightUnits light_units = PunctualLightUnits::Watts;
    /// The diffuse base of every glTF material (MetallicRoughness): glTF's Lambert, or
    /// Burley's as Blender's Principled BSDF has it (rt_render --diffuse burley).
    DiffuseModel diffuse_model = DiffuseModel::Lambert;
    /// A glTF material with KHR_materials_transmission and no KHR_materials_volume is
    /// thin-walled (the specification's default, with a hint naming it); true: solid glass,
    /// refracting through closed meshes, as Blender and Cycles show it (rt_render
    /// --solid-transmission). See material_from_gltf for which materials can be.
    bool solid_transmission = false;
};

/// A scene file as librt renders it.
struct LoadedScene {
    Scene scene;            ///< geometry, materials, lights; not yet committed
    CameraSettings camera;  ///< pinhole, no pixel jitter (the app chooses that)
    /// Which camera: the file's name for it, as the file gives it (show it with
    /// quote_untrusted: it may hold control characters), or "default".
    std::string camera_name;
    std::vector<std::string> warnings;  ///< what was skipped or replaced, one line each
    /// When default lighting was added, what it is, one line (for the app to show once);
    /// else empty.
    std::string lighting_note;
    std::size_t triangles_stored = 0;  ///< triangles held once per prototype / mesh
    std::size_t triangles_placed = 0;  ///< triangles over all instances
    BBox bounds;                       ///< world bounds of the geometry
    /// Every file the scene was made from, each distinct file once, in the order read: the
    /// scene file first (its path as given), then the files it names (glTF buffers and the
    /// images textures use; an OBJ's MTL files and map_Kd images) by the path they were
    /// opened at. An image that could not be read or decoded (a warning) is not listed.
    /// Each digest is of the bytes the loader used, taken from memory (no file is read
    /// twice): what the ranks of an MPI job compare, so that none renders a different .bin
    /// or texture unnoticed.
    std::vector<FileRead> files_read;
};

/// A camera framing `bounds` (film/framing.h, frame_bounds with its defaults: a vertical
/// field of view of 40 degrees, the box filling the frame but for a 5 % margin, seen from the
/// front, +z, 15 degrees above the horizon), y up, at the given image size. Throws
/// librt::Error for an empty or non-finite box.
[[nodiscard]] LIBRT_API CameraSettings default_camera(const BBox& bounds, int width, int height);

/// `camera` with `view` applied (apply_view, `framed` when it is default_camera's), its
/// errors prefixed "view: "; an orbit names the camera "default" in `camera_name` (it is the
/// framing camera). The loaders call it before placing the default lighting.
[[nodiscard]] LIBRT_API CameraSettings view_camera(const CameraSettings& camera, bool framed,
                                                   const BBox& bounds, const ViewOptions& view,
                                                   std::string& camera_name);

}  // namespace librt
