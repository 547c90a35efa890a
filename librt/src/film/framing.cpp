#include <librt/core/error.h>
#include <librt/film/framing.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace librt {

namespace {

/// The eight corners of a box.
std::array<glm::dvec3, 8> corners(const BBox& b) {
    std::array<glm::dvec3, 8> c;
    for (int i = 0; i < 8; ++i) {
        c[std::size_t(i)] =
            glm::dvec3((i & 1) != 0 ? b.hi.x : b.lo.x, (i & 2) != 0 ? b.hi.y : b.lo.y,
                       (i & 4) != 0 ? b.hi.z : b.lo.z);
    }
    return c;
}

/// The camera's axes: right, up and back (toward the camera).
struct Frame {
    glm::dvec3 right, up, back;
};

Frame frame_of(const glm::vec3& view_from) {
    Frame f;
    f.back = glm::normalize(glm::dvec3(view_from));
    // Looking straight down or up, world +y cannot be the image's up: -z takes its place.
    const glm::dvec3 world_up =
        std::abs(f.back.y) > 0.999 ? glm::dvec3(0, 0, -1) : glm::dvec3(0, 1, 0);
    f.right = glm::normalize(glm::cross(world_up, f.back));
    f.up = glm::cross(f.back, f.right);
    return f;
}

/// One image axis of the fit: the corners' coordinates along it (a) and along the view
/// toward the camera (z), relative to the box's centre, and t the tangent of the half field of
/// view there. Moving the camera sideways by s along the axis and back to distance d from
/// the centre's plane puts corner i at (a_i - s) / (d - z_i) on the image plane; inside
/// means |a_i - s| <= t (d - z_i).
struct Axis {
    std::array<double, 8> a{}, z{};
    double t = 1.0;

    /// The smallest d for which some s puts every corner inside: s must lie in
    /// [max_i a_i - t (d - z_i), min_j a_j + t (d - z_j)], which is not empty when
    /// a_i - a_j <= t (2 d - z_i - z_j) for every pair.
    [[nodiscard]] double closest() const {
        double d = 0.0;
        for (std::size_t i = 0; i < 8; ++i) {
            for (std::size_t j = 0; j < 8; ++j)
                d = std::max(d, (a[i] - a[j]) / (2.0 * t) + 0.5 * (z[i] + z[j]));
        }
        return d;
    }
    /// At distance d (>= closest()), the middle of the shifts that keep every corner inside:
    /// the box centred along this axis (exactly touching both edges when d == closest()).
    [[nodiscard]] double shift(double d) const {
        double lo = -1e300, hi = 1e300;
        for (std::size_t i = 0; i < 8; ++i) {
            lo = std::max(lo, a[i] - t * (d - z[i]));
            hi = std::min(hi, a[i] + t * (d - z[i]));
        }
        return 0.5 * (lo + hi);
    }
};

}  // namespace

glm::vec3 default_view_direction() {
    const float e = glm::radians(15.0f);
    return {0.0f, std::sin(e), std::cos(e)};
}

CameraSettings frame_bounds(const BBox& bounds, int width, int height,
                            const FramingOptions& options) {
    const bool finite = std::isfinite(bounds.lo.x) && std::isfinite(bounds.lo.y) &&
                        std::isfinite(bounds.lo.z) && std::isfinite(bounds.hi.x) &&
                        std::isfinite(bounds.hi.y) && std::isfinite(bounds.hi.z);
    if (bounds.empty() || !finite) throw Error("frame_bounds: bounds empty or not finite");
    if (width < 1 || height < 1 || width > 65536 || height > 65536)
        throw Error("frame_bounds: size = " + std::to_string(width) + "x" + std::to_string(height) +
                    ": each side must be in [1, 65536]");
    const float fov = options.vertical_fov_degrees;
    if (!(fov > 0.0f && fov < 179.0f))
        throw Error("frame_bounds: vertical_fov_degrees = " + std::to_string(fov) +
                    ": must be in (0, 179)");
    if (!(options.margin >= 0.0f && options.margin < 0.5f))
        throw Error("frame_bounds: margin = " + std::to_string(options.margin) +
                    ": must be in [0, 0.5)");
    const glm::vec3 v = options.view_from;
    if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) ||
        glm::dot(v, v) < 1e-20f)
        throw Error("frame_bounds: view_from must be finite and not zero");

    const Frame f = frame_of(v);
    const double aspect = double(width) / double(height);
    const double ty = std::tan(glm::radians(0.5 * double(fov))) * (1.0 - double(options.margin));
    const double tx = ty * aspect;
    const std::array<glm::dvec3, 8> pts = corners(bounds);
    const glm::dvec3 lo(bounds.lo), hi(bounds.hi);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    Axis horizontal, vertical;
    horizontal.t = tx;
    vertical.t = ty;
    double nearest = -1e300;  // the corner closest to the camera, along the view
    for (std::size_t i = 0; i < 8; ++i) {
        const glm::dvec3 r = pts[i] - centre;
        horizontal.a[i] = glm::dot(r, f.right);
        vertical.a[i] = glm::dot(r, f.up);
        horizontal.z[i] = vertical.z[i] = glm::dot(r, f.back);
        nearest = std::max(nearest, horizontal.z[i]);
    }
    // The closest distance both axes allow (perspective makes the box's near half look
    // bigger, so the optical axis moves sideways to centre it: an exact fit, not the
    // bounding sphere's), and at least a little in front of the nearest corner, so that a
    // point or a flat box still gets a camera in front of it.
    const double min_depth = std::max(1e-6, 1e-3 * glm::length(hi - lo));
    const double d = std::max({horizontal.closest(), vertical.closest(), nearest + min_depth});
    const glm::dvec3 target = centre + horizontal.shift(d) * f.right + vertical.shift(d) * f.up;

    CameraSettings c;
    c.width = width;
    c.height = height;
    c.vertical_fov_degrees = fov;
    c.look_at = glm::vec3(target);
    c.position = glm::vec3(target + d * f.back);
    c.up = glm::vec3(f.up);
    c.focal_distance = float(d);
    return c;
}

namespace {

std::string text_of(const glm::vec3& p) {
    return std::to_string(p.x) + "," + std::to_string(p.y) + "," + std::to_string(p.z);
}

bool finite3(const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace

CameraSettings apply_view(const CameraSettings& camera, bool framed, const BBox& bounds,
                          const ViewOptions& view) {
    CameraSettings c = camera;
    if (view.empty()) return c;
    if (view.look_from && !finite3(*view.look_from))
        throw Error("look_from = " + text_of(*view.look_from) + ": must be finite");
    if (view.look_at && !finite3(*view.look_at))
        throw Error("look_at = " + text_of(*view.look_at) + ": must be finite");
    if (const std::optional<float> fov = view.vertical_fov_degrees) {
        if (!(*fov > 0.0f && *fov < 179.0f))
            throw Error("vertical_fov_degrees = " + std::to_string(*fov) + ": must be in (0, 179)");
        if (c.projection == Projection::Orthographic)
            throw Error("vertical_fov_degrees = " + std::to_string(*fov) +
                        ": the camera is orthographic (it has no field of view)");
    }
    if (const std::optional<float> orbit = view.orbit_degrees) {
        if (!(std::abs(*orbit) <= 360.0f))
            throw Error("orbit_degrees = " + std::to_string(*orbit) + ": must be in [-360, 360]");
        if (view.look_from || view.look_at)
            throw Error("orbit_degrees = " + std::to_string(*orbit) +
                        ": turns the framing camera; not with look_from or look_at");
    }
    // Reframed: an orbit, or a new field of view for a camera that framed the bounds.
    if (view.orbit_degrees ||
        (framed && view.vertical_fov_degrees && !view.look_from && !view.look_at)) {
        FramingOptions framing;
        if (view.vertical_fov_degrees) framing.vertical_fov_degrees = *view.vertical_fov_degrees;
        // Counter-clockwise seen from above (+y): +z turns toward +x.
        const float turn = glm::radians(view.orbit_degrees.value_or(0.0f));
        const glm::vec3 d = default_view_direction();
        framing.view_from = {d.x * std::cos(turn) + d.z * std::sin(turn), d.y,
                             -d.x * std::sin(turn) + d.z * std::cos(turn)};
        CameraSettings f = frame_bounds(bounds, c.width, c.height, framing);
        f.pixel_jitter = c.pixel_jitter;
        f.pixel_sigma = c.pixel_sigma;
        f.pixel_filter = c.pixel_filter;
        return f;
    }
    if (view.vertical_fov_degrees) c.vertical_fov_degrees = *view.vertical_fov_degrees;
    if (!view.look_from && !view.look_at) return c;
    if (view.look_from) {
        c.position = *view.look_from;
        if (!view.look_at) {
            if (bounds.empty()) throw Error("look_from: the scene has no bounds to look at");
            c.look_at = 0.5f * (bounds.lo + bounds.hi);
        }
    }
    if (view.look_at) c.look_at = *view.look_at;
    const glm::vec3 axis = c.look_at - c.position;
    const float length = glm::length(axis);
    if (!(length > 0.0f) || !std::isfinite(length))
        throw Error("look_from = " + text_of(c.position) + ", look_at = " + text_of(c.look_at) +
                    ": the camera must stand away from the point it looks at");
    // Straight down or up, +y cannot be the image's up: -z takes its place (frame_bounds').
    c.up = std::abs(axis.y / length) > 0.999f ? glm::vec3(0.0f, 0.0f, -1.0f)
                                              : glm::vec3(0.0f, 1.0f, 0.0f);
    c.focal_distance = length;
    return c;
}

}  // namespace librt
