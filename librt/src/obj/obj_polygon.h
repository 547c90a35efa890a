#pragma once

// Private: triangulation of an OBJ polygon face (more than three corners) by ear clipping
// in its own plane, for load_obj.

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace librt::detail {

/// Reusable buffers for triangulate_polygon, so faces allocate nothing once warmed up.
struct PolygonScratch {
    std::vector<glm::dvec2> points;
    std::vector<std::size_t> remaining;
};

/// What triangulate_polygon made of a polygon.
enum class Polygon {
    Triangulated,  ///< triangles appended, covering exactly the polygon's area
    ZeroArea,      ///< nothing appended: the polygon has no area
    NotSimple,     ///< nothing appended: self-overlapping, no area-preserving triangulation
};

/// Ear clipping (Meisters' two-ears theorem: a simple polygon always has an ear to cut) in the
/// polygon's own plane, appending triangles with the polygon's winding. Corners that add no
/// area are dropped first: repeats of the previous corner and the tips of zero-width spikes
/// (the boundary running out and back along one line), so weakly simple polygons triangulate
/// too. A polygon that is not simple may run out of ears; the rest is then fanned, and if the
/// triangles' total area differs from the polygon's (they overlap) nothing is appended.
Polygon triangulate_polygon(const std::vector<glm::vec3>& positions,
                            const std::vector<std::uint32_t>& corners, PolygonScratch& scratch,
                            std::vector<glm::uvec3>& out);

}  // namespace librt::detail
