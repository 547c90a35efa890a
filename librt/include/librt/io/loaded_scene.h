#pragma once

#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/geometry/bbox.h>
#include <librt/io/file_digest.h>
#include <librt/light/point_light.h>
#include <librt/scene/scene.h>

#include <cstddef>
#include <string>
#include <vector>

// What a scene file (glTF or OBJ) becomes: a Scene ready to commit, the camera to render
// it through, and what had to be left out. gltf/gltf_scene.h and loader/scene_file.h fill it.

namespace librt {

/// How a scene file is turned into a Scene and a camera.
struct SceneFileOptions {
    /// The file's camera to use (perspective or orthographic): empty = the first; all digits = the
    /// index among the cameras the scene places (node order); else a camera (or its
    /// node's) name. A file without cameras gets default_camera().
    std::string camera;
    int width = 0;   ///< image width; 0 (with height 0) = from the camera's aspect ratio
    int height = 0;  ///< image height; 0 (with width 0) = from the camera's aspect ratio
    /// Longest image side when the size follows the camera's aspect ratio.
    int default_long_side = 640;
    /// Let the scene read files outside its own directory tree (GltfLoadOptions and
    /// ObjLoadOptions::allow_outside_files): only for a file you trust.
    bool allow_outside_files = false;
};

/// A scene file as librt renders it.
struct LoadedScene {
    Scene scene;            ///< geometry, materials, lights; not yet committed
    CameraSettings camera;  ///< pinhole, no pixel jitter (the app chooses that)
    /// Which camera: the file's name for it, as the file gives it (show it with
    /// quote_untrusted: it may hold control characters), or "default".
    std::string camera_name;
    std::vector<std::string> warnings;  ///< what was skipped or replaced, one line each
    std::size_t triangles_stored = 0;   ///< triangles held once per prototype / mesh
    std::size_t triangles_placed = 0;   ///< triangles over all instances
    BBox bounds;                        ///< world bounds of the geometry
    /// Every file the scene was made from, each distinct file once, in the order read: the
    /// scene file first (its path as given), then the files it names (glTF buffers and the
    /// images textures use; an OBJ's MTL files and map_Kd images) by the path they were
    /// opened at. An image that could not be read or decoded (a warning) is not listed.
    /// Each digest is of the bytes the loader used, taken from memory (no file is read
    /// twice): what the ranks of an MPI job compare, so that none renders a different .bin
    /// or texture unnoticed.
    std::vector<FileRead> files_read;
};

/// A camera framing `bounds` (its bounding sphere fills the vertical field of view of
/// 40 degrees) from the front (+z), a little above and to the right, y up, at the given
/// image size. Throws librt::Error for an empty or non-finite box.
[[nodiscard]] LIBRT_API CameraSettings default_camera(const BBox& bounds, int width, int height);

/// The light a file without light gets: a point light above, left of and in front of the
/// bounds' centre, at three bounding-sphere radii, whose irradiance at the centre is pi
/// W/m^2 (a white Lambertian surface facing it has radiance 1). Throws librt::Error for an
/// empty or non-finite box.
[[nodiscard]] LIBRT_API PointLight default_light(const BBox& bounds);

}  // namespace librt
