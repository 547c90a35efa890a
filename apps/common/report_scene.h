#pragma once

#include <librt/film/camera.h>
#include <librt/geometry/mesh.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>

// The report's scene ("the room", docs/scenes.md) built through librt's public API.

namespace librt::apps {

/// The report's light intensity I = 2.14e8, used by it as a power in I / (4 pi d^2).
inline constexpr float kReportPower = 2.14e8f;
/// Default light power of every app: the report summed its samples instead of averaging
/// them, and its 80-sample figures look like an averaged render at 80 x 2.14e8.
inline constexpr float kDefaultPower = 80.0f * kReportPower;
/// Centre of the report's light (point or sphere).
inline constexpr glm::vec3 kLightCenter{-10.0f, 20.0f, 40.0f};
/// Radius of the report's light sphere.
inline constexpr float kLightRadius = 10.0f;

/// The report's lights.
enum class LightKind {
    Point,   ///< point light at kLightCenter (hard shadows)
    Sphere,  ///< light sphere of radius kLightRadius at kLightCenter (soft shadows)
};

/// Adds the six huge diffuse spheres that form the room (floor at y = -10, coloured walls).
void add_room(Scene& scene);

/// Adds the report's four spheres: white and green diffuse, a mirror, and glass of index
/// 1.4 that always refracts as in the report.
void add_report_spheres(Scene& scene);

/// Adds the report's light of the given total power (same in every channel).
void add_report_light(Scene& scene, LightKind kind, float power);

/// The report's scene without a mesh: add_room, add_report_spheres, add_report_light.
void add_report_scene(Scene& scene, LightKind light, float power);

/// The report's camera: at (0, 0, 55) looking down -z, 60 degree vertical fov.
[[nodiscard]] CameraSettings report_camera(int width, int height);

/// Where and how a mesh goes into the room: fitted, then the report's transform.
struct MeshPlacement {
    /// Largest bounding-box side after fitting, in model units, with the box's bottom centre
    /// moved to the origin; 0 keeps the file's coordinates as they are (as the report did).
    float fit = 0.75f;
    float scale = 20.0f;                   ///< the report's scale
    glm::vec3 offset{0.0f, -10.0f, 0.0f};  ///< the report's offset (puts y = 0 on the floor)
    float rotate_y_degrees = 0.0f;         ///< turn about +y before scaling
};

/// The default mesh when no file is given: a Utah teapot of ~5.5k triangles (the size of
/// the report's character), turned -45 degrees so its spout faces the camera's right.
[[nodiscard]] TriangleMesh default_mesh();

/// Fits, rotates, scales and moves the mesh as `placement` says.
void place_mesh(TriangleMesh& mesh, const MeshPlacement& placement);

/// Loads `path` (OBJ with its MTL) or, when empty, builds default_mesh(), and places it.
[[nodiscard]] TriangleMesh load_report_mesh(const std::filesystem::path& path,
                                            const MeshPlacement& placement);

/// Adds the mesh with its MTL materials, or `fallback` when it has none of its own.
void add_report_mesh(Scene& scene, TriangleMesh mesh, const Material& fallback,
                     BvhBuilder builder = BvhBuilder::Sah);

}  // namespace librt::apps
