#include "film/camera_importance.h"

#include <librt/core/constants.h>
#include <librt/sampling/jitter.h>

#include <glm/ext/vector_double2.hpp>
#include <glm/ext/vector_double3.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace librt {

namespace {

// What the functions of the header share about one ray from a lens point.
struct LensRay {
    glm::dvec2 raster{0.0};  // where it meets the image, in pixels
    double cos_lens = 0.0;   // cosine between the ray and forward() (the lens normal)
    double pdf_dir = 0.0;    // solid-angle density of its direction (CameraPdf::dir)
};

glm::dvec3 to_double(const glm::vec3& v) { return glm::dvec3(v); }

// The pinhole projection of q (a point relative to the position) onto the raster, and the
// cosine of q with the optical axis; nothing for q not strictly in front.
std::optional<glm::dvec2> project(const Camera& camera, const glm::dvec3& q) {
    const double z = glm::dot(q, to_double(camera.forward()));
    if (!(z > 0.0)) return std::nullopt;
    const double d = camera.image_plane_distance();
    // Inverse of sample_ray's direction (x - W/2, H/2 - y, d) in the look-at basis.
    const double x = 0.5 * camera.width() + d * glm::dot(q, to_double(camera.right())) / z;
    const double y = 0.5 * camera.height() - d * glm::dot(q, to_double(camera.true_up())) / z;
    return glm::dvec2(x, y);
}

bool on_image(const Camera& camera, const glm::dvec2& raster, double margin) {
    return raster.x >= -margin && raster.x < camera.width() + margin && raster.y >= -margin &&
           raster.y < camera.height() + margin;
}

// The image's area on the plane at unit distance from the position: (W / d) (H / d).
double image_area(const Camera& camera) {
    const double d = camera.image_plane_distance();
    return static_cast<double>(camera.width()) * static_cast<double>(camera.height()) / (d * d);
}

// The ray from `origin` (a lens point; ignored for a delta lens) in unit direction `dir`,
// or nothing when it misses the image grown by `margin`.
std::optional<LensRay> trace(const Camera& camera, const glm::dvec3& origin, const glm::dvec3& dir,
                             double margin) {
    if (camera.settings().projection != Projection::Perspective) return std::nullopt;
    LensRay out;
    out.cos_lens = glm::dot(dir, to_double(camera.forward()));
    if (!(out.cos_lens > 0.0)) return std::nullopt;
    const double area = image_area(camera);
    if (lens_is_delta(camera)) {
        const auto raster = project(camera, dir);
        if (!raster || !on_image(camera, *raster, margin)) return std::nullopt;
        out.raster = *raster;
        // Density of the direction through a raster position uniform over the image: the
        // unit-distance plane's dA = dw / cos^3 (Pharr, Jakob, Humphreys, pbrt 3rd ed., sec.
        // 16.1.1 "Sampling Cameras"; pbrt-v4 keeps it in PerspectiveCamera::PDF_We).
        out.pdf_dir = 1.0 / (area * out.cos_lens * out.cos_lens * out.cos_lens);
        return out;
    }
    // The in-focus point: sample_ray aims a lens ray at p = position + F u, u the unit
    // pinhole direction, so p is where the ray leaves the sphere |p - position| = F. With
    // o = origin - position: t^2 + 2 b t + c = 0, b = o.dir, c = |o|^2 - F^2; the larger
    // root, written without cancellation.
    const double focal = camera.settings().focal_distance;
    const glm::dvec3 o = origin - to_double(camera.settings().position);
    const double b = glm::dot(o, dir);
    const double c = glm::dot(o, o) - focal * focal;
    const double disc = b * b - c;
    if (!(disc >= 0.0)) return std::nullopt;
    const double root = std::sqrt(disc);
    const double t = b <= 0.0 ? root - b : -c / (b + root);
    if (!(t > 0.0)) return std::nullopt;
    const glm::dvec3 p = o + t * dir;
    const auto raster = project(camera, p);
    if (!raster || !on_image(camera, *raster, margin)) return std::nullopt;
    out.raster = *raster;
    const glm::dvec3 u = p / focal;
    const double cos_u = glm::dot(u, to_double(camera.forward()));
    // The ray leaves the sphere at cosine (b + t) / F with its normal u; 0 is a tangent.
    const double cos_exit = (b + t) / focal;
    if (!(cos_exit > 0.0) || !(cos_u > 0.0)) return std::nullopt;
    // Change of variables u -> dir through the in-focus point: dw_u = dA_p / F^2 (seen
    // from the centre) and dw_dir = cos_exit dA_p / t^2 (seen from the lens point), so
    // pdf_dir = pdf_u(u) t^2 / (F^2 cos_exit), pdf_u = 1 / (A cos_u^3) as for the pinhole.
    out.pdf_dir = t * t / (area * cos_u * cos_u * cos_u * focal * focal * cos_exit);
    return out;
}

// The lens point's density per unit lens area (CameraPdf::pos); `origin` a lens point.
double lens_pdf(const Camera& camera, const glm::dvec3& origin) {
    const CameraSettings& s = camera.settings();
    if (lens_is_delta(camera)) return 1.0;
    if (s.lens == LensModel::Disk) {
        // Uniform over the disk (disk_lens_jitter).
        return 1.0 / (kPiDouble * double(s.lens_radius) * double(s.lens_radius));
    }
    // The 2D normal density of gaussian_lens_jitter's offset: exp(-|l|^2 / (2 s^2)) /
    // (2 pi s^2) (Box-Muller's cap at 13.2 sigma is below anything a float can resolve).
    const glm::dvec3 o = origin - to_double(s.position);
    const double lx = glm::dot(o, to_double(camera.right()));
    const double ly = glm::dot(o, to_double(camera.true_up()));
    const double var = double(s.lens_sigma) * double(s.lens_sigma);
    return std::exp(-(lx * lx + ly * ly) / (2.0 * var)) / (2.0 * kPiDouble * var);
}

std::optional<LensRay> trace_ray(const Camera& camera, const Ray& ray, float margin) {
    const glm::dvec3 dir = glm::normalize(to_double(ray.direction));
    if (!(std::isfinite(dir.x) && std::isfinite(dir.y) && std::isfinite(dir.z))) {
        return std::nullopt;
    }
    return trace(camera, to_double(ray.origin), dir, double(margin));
}

}  // namespace

bool lens_is_delta(const Camera& camera) {
    const CameraSettings& s = camera.settings();
    return s.projection != Projection::Perspective || s.lens == LensModel::Pinhole ||
           (s.lens == LensModel::Disk && s.lens_radius == 0.0f) ||
           (s.lens == LensModel::Gaussian && s.lens_sigma == 0.0f);
}

std::optional<glm::vec2> raster_of(const Camera& camera, const Ray& ray, float margin) {
    const auto traced = trace_ray(camera, ray, margin);
    if (!traced) return std::nullopt;
    return glm::vec2(traced->raster);
}

CameraPdf pdf_we(const Camera& camera, const Ray& ray, float margin) {
    const auto traced = trace_ray(camera, ray, margin);
    if (!traced) return {};
    return {static_cast<float>(lens_pdf(camera, to_double(ray.origin))),
            static_cast<float>(traced->pdf_dir)};
}

float camera_importance(const Camera& camera, const Ray& ray, float margin) {
    const auto traced = trace_ray(camera, ray, margin);
    if (!traced) return 0.0f;
    // We = pdf_dir / cos: integral We cos dw = integral pdf_dir dw = 1 over the image.
    return static_cast<float>(traced->pdf_dir / traced->cos_lens);
}

CameraWi sample_wi(const Camera& camera, const glm::vec3& ref, glm::vec2 u_lens, float margin) {
    CameraWi out;
    const CameraSettings& s = camera.settings();
    if (s.projection != Projection::Perspective) return out;
    out.delta = lens_is_delta(camera);
    // The lens point exactly as sample_ray computes it from its lens sample.
    glm::vec3 lens_point = s.position;
    if (!out.delta) {
        const glm::vec2 l = s.lens == LensModel::Gaussian
                                ? gaussian_lens_jitter(u_lens, s.lens_sigma)
                                : disk_lens_jitter(u_lens, s.lens_radius);
        lens_point = s.position + l.x * camera.right() + l.y * camera.true_up();
    }
    const glm::dvec3 to_ref = to_double(ref) - to_double(lens_point);
    const double distance = glm::length(to_ref);
    if (!(distance > 0.0) || !std::isfinite(distance)) return out;
    const glm::dvec3 dir = to_ref / distance;
    // A camera ray sees only hits at depths in (near_clip, far_clip) before the lens plane,
    // or with a near clip distance, at distances beyond near_clip and depths before far_clip.
    const double depth = glm::dot(to_ref, to_double(camera.forward()));
    const bool near_distance = s.near_clip_mode == NearClipMode::Distance;
    if (!(depth > 0.0 && (near_distance ? distance : depth) > double(s.near_clip) &&
          depth < double(s.far_clip))) {
        return out;
    }
    const auto traced = trace(camera, to_double(lens_point), dir, double(margin));
    if (!traced) return out;
    const double pdf_pos = lens_pdf(camera, to_double(lens_point));
    out.valid = true;
    out.lens_point = lens_point;
    // The near plane at t = near / cos_axis along the unit direction, cos_axis = depth / d;
    // a near clip distance at t = near.
    const double view_t =
        near_distance ? double(s.near_clip) : double(s.near_clip) * distance / depth;
    out.view_start =
        s.near_clip > 0.0f ? glm::vec3(to_double(lens_point) + dir * view_t) : lens_point;
    out.wi = glm::vec3(-dir);
    out.distance = static_cast<float>(distance);
    out.raster = glm::vec2(traced->raster);
    out.importance = static_cast<float>(traced->pdf_dir / traced->cos_lens);
    out.pdf_pos = static_cast<float>(pdf_pos);
    // Area density on the lens to solid angle at ref: dA = d^2 dw / cos_lens.
    out.pdf =
        out.delta ? 1.0f : static_cast<float>(pdf_pos * distance * distance / traced->cos_lens);
    // We cos_lens / d^2 = pdf_dir / d^2: the film estimate's factor (see the header).
    out.weight = static_cast<float>(traced->pdf_dir / (distance * distance));
    return out;
}

FilterSettings splat_filter_settings(const Camera& camera) {
    const CameraSettings& s = camera.settings();
    if (s.pixel_jitter == PixelJitter::Filter) return s.pixel_filter;
    FilterSettings box;  // radius 0.5: the pixel
    if (s.pixel_jitter == PixelJitter::Gaussian && s.pixel_sigma > 0.0f) {
        FilterSettings gaussian;
        gaussian.kind = FilterKind::Gaussian;
        gaussian.sigma = s.pixel_sigma;
        gaussian.radius = std::numeric_limits<float>::infinity();
        return gaussian;
    }
    return box;
}

}  // namespace librt
