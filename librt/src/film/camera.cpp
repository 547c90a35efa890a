#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/film/camera.h>
#include <librt/sampling/jitter.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace librt {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& value, const char* rule) {
    throw Error("camera " + name + " = " + value + ": " + rule);
}

std::string to_text(float v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

std::string to_text(const glm::vec3& v) {
    std::ostringstream out;
    out << '(' << v.x << ", " << v.y << ", " << v.z << ')';
    return out.str();
}

void validate(const CameraSettings& s) {
    constexpr int kMaxSize = 65536;
    if (s.width < 1 || s.width > kMaxSize) {
        fail("width", std::to_string(s.width), "must be in [1, 65536]");
    }
    if (s.height < 1 || s.height > kMaxSize) {
        fail("height", std::to_string(s.height), "must be in [1, 65536]");
    }
    const int projection = static_cast<int>(s.projection);
    if (projection < static_cast<int>(Projection::Perspective) ||
        projection > static_cast<int>(Projection::Orthographic)) {
        fail("projection", std::to_string(projection), "is not a Projection");
    }
    if (s.projection == Projection::Perspective) {
        if (!(s.vertical_fov_degrees > 0.0f && s.vertical_fov_degrees < 180.0f)) {
            fail("vertical_fov_degrees", to_text(s.vertical_fov_degrees), "must be in (0, 180)");
        }
    } else {
        // 2 xmag must stay finite too: it is the image's width in scene units.
        if (!(s.xmag > 0.0f) || !std::isfinite(2.0f * s.xmag)) {
            fail("xmag", to_text(s.xmag), "must be finite and > 0 (orthographic half width)");
        }
        if (!(s.ymag > 0.0f) || !std::isfinite(2.0f * s.ymag)) {
            fail("ymag", to_text(s.ymag), "must be finite and > 0 (orthographic half height)");
        }
        // Parallel rays have no centre of projection to focus through.
        if (s.lens != LensModel::Pinhole) {
            fail("lens", std::to_string(static_cast<int>(s.lens)),
                 "must be Pinhole for an orthographic camera (no depth of field)");
        }
    }
    if (!finite(s.position)) fail("position", to_text(s.position), "must be finite");
    if (!finite(s.look_at)) fail("look_at", to_text(s.look_at), "must be finite");
    if (!finite(s.up)) fail("up", to_text(s.up), "must be finite");
    const glm::vec3 view = s.look_at - s.position;
    if (!std::isfinite(glm::length(view))) {
        fail("look_at", to_text(s.look_at), "is too far from position (overflows float)");
    }
    if (!(glm::length(view) > 0.0f))
        fail("look_at", to_text(s.look_at), "must differ from position");
    if (!(glm::length(s.up) > 0.0f)) fail("up", to_text(s.up), "must not be zero");
    if (!std::isfinite(glm::length(s.up)))
        fail("up", to_text(s.up), "is too long (overflows float)");
    // |sin| of the angle between up and the view direction; below ~1e-4 rad the
    // basis would be numerically meaningless.
    const float sin_angle = glm::length(glm::cross(glm::normalize(view), glm::normalize(s.up)));
    if (!(sin_angle > 1e-4f)) {
        fail("up", to_text(s.up), "must not be parallel to the view direction");
    }
    if (!(s.pixel_sigma >= 0.0f) || !std::isfinite(s.pixel_sigma)) {
        fail("pixel_sigma", to_text(s.pixel_sigma), "must be finite and >= 0");
    }
    if (!(s.lens_sigma >= 0.0f) || !std::isfinite(s.lens_sigma)) {
        fail("lens_sigma", to_text(s.lens_sigma), "must be finite and >= 0");
    }
    if (!(s.lens_radius >= 0.0f) || !std::isfinite(s.lens_radius)) {
        fail("lens_radius", to_text(s.lens_radius), "must be finite and >= 0");
    }
    if (!(s.focal_distance > 0.0f) || !std::isfinite(s.focal_distance)) {
        fail("focal_distance", to_text(s.focal_distance), "must be finite and > 0");
    }
    const int jitter = static_cast<int>(s.pixel_jitter);
    if (jitter < static_cast<int>(PixelJitter::None) ||
        jitter > static_cast<int>(PixelJitter::Filter)) {
        fail("pixel_jitter", std::to_string(jitter), "is not a PixelJitter");
    }
    if (!(s.near_clip >= 0.0f) || !std::isfinite(s.near_clip)) {
        fail("near_clip", to_text(s.near_clip), "must be finite and >= 0");
    }
    const int near_mode = static_cast<int>(s.near_clip_mode);
    if (near_mode < static_cast<int>(NearClipMode::Plane) ||
        near_mode > static_cast<int>(NearClipMode::Distance)) {
        fail("near_clip_mode", std::to_string(near_mode), "is not a NearClipMode");
    }
    // In Distance mode too: t_max = far_clip / cos >= far_clip > near_clip = t_min.
    if (!(s.far_clip > s.near_clip)) {
        fail("far_clip", to_text(s.far_clip), "must be > near_clip (+inf for no far clip)");
    }
}

PixelFilter make_filter(const CameraSettings& s) {
    if (s.pixel_jitter != PixelJitter::Filter) return PixelFilter{};
    try {
        return PixelFilter(s.pixel_filter);
    } catch (const Error& e) {
        throw Error(std::string("camera pixel_filter: ") + e.what());
    }
}

}  // namespace

// Inlined into both callers: a call here cost the report's scenes 1.4% of their camera time.
[[gnu::always_inline]] inline glm::vec2 Camera::pixel_offset(glm::vec2 pixel_u,
                                                             float& weight) const {
    if (settings_.pixel_jitter == PixelJitter::Gaussian) {
        return gaussian_pixel_jitter(pixel_u, settings_.pixel_sigma);
    }
    if (settings_.pixel_jitter == PixelJitter::Filter) {
        const FilterSample f = filter_.sample(pixel_u);
        weight = f.weight;
        return f.offset;
    }
    return glm::vec2(0.0f);
}

Camera::Camera(const CameraSettings& settings) : settings_(settings) {
    validate(settings_);
    filter_ = make_filter(settings_);
    clipped_ = settings_.near_clip > 0.0f || std::isfinite(settings_.far_clip);
    // Look-at basis: forward, right = forward x up, true up = right x forward.
    forward_ = glm::normalize(settings_.look_at - settings_.position);
    right_ = glm::normalize(glm::cross(forward_, settings_.up));
    up_ = glm::cross(right_, forward_);
    const double half_fov =
        0.5 * static_cast<double>(settings_.vertical_fov_degrees) * kPiDouble / 180.0;
    // The report's image-plane distance: H / (2 tan(fov/2)) pixels.
    image_plane_distance_ =
        static_cast<float>(static_cast<double>(settings_.height) / (2.0 * std::tan(half_fov)));
    // glTF's orthographic projection maps [-xmag, xmag] x [-ymag, ymag] onto the image.
    ortho_pixel_size_ = {2.0f * settings_.xmag / static_cast<float>(settings_.width),
                         2.0f * settings_.ymag / static_cast<float>(settings_.height)};
}

CameraRay Camera::perspective_ray(int px, int py, Sampler& sampler) const {
    const glm::vec2 pixel_u = sampler.next_2d();
    const glm::vec2 lens_u = sampler.next_2d();

    float weight = 1.0f;
    const glm::vec2 offset = pixel_offset(pixel_u, weight);
    // The lens offset before the direction: its log and sincos calls then come before the
    // camera's vectors are loaded, which would otherwise be saved and restored around each
    // call (callgrind on the synthesis: ~50 instructions per ray). The same values.
    glm::vec2 lens{0.0f};
    if (settings_.lens != LensModel::Pinhole) {
        lens = settings_.lens == LensModel::Gaussian
                   ? gaussian_lens_jitter(lens_u, settings_.lens_sigma)
                   : disk_lens_jitter(lens_u, settings_.lens_radius);
    }
    const float half_w = 0.5f * static_cast<float>(settings_.width);
    const float half_h = 0.5f * static_cast<float>(settings_.height);
    // The report's camera-space direction: (j - W/2 + 0.5 + dx, -i + H/2 - 0.5 + dy, -d).
    const float cx = static_cast<float>(px) - half_w + 0.5f + offset.x;
    const float cy = -static_cast<float>(py) + half_h - 0.5f + offset.y;
    const glm::vec3 u = glm::normalize(cx * right_ + cy * up_ + image_plane_distance_ * forward_);

    CameraRay out;
    out.weight = weight;
    Ray& ray = out.ray;
    ray.origin = settings_.position;
    ray.direction = u;
    if (settings_.lens != LensModel::Pinhole) {
        // The report's depth of field: C' = C + lens offset in the camera's x-y plane,
        // aimed at the focal point C + focal_distance * u.
        const glm::vec3 focal_point = settings_.position + settings_.focal_distance * u;
        ray.origin = settings_.position + lens.x * right_ + lens.y * up_;
        ray.direction = glm::normalize(focal_point - ray.origin);
    }
    // Clip planes at depth near/far from the lens plane: along the unit direction that is
    // t = depth / cos(angle to the view axis); a near clip distance is t itself. Skipped
    // without clips so that t_min = 0 and t_max = inf stay exact.
    if (clipped_) {
        const float cos_axis = glm::dot(ray.direction, forward_);
        ray.t_min = settings_.near_clip_mode == NearClipMode::Distance
                        ? settings_.near_clip
                        : settings_.near_clip / cos_axis;
        ray.t_max = settings_.far_clip / cos_axis;
    }
    return out;
}

CameraRay Camera::orthographic_ray(int px, int py, Sampler& sampler) const {
    const glm::vec2 pixel_u = sampler.next_2d();
    (void)sampler.next_2d();  // the lens sample, drawn as by a perspective camera
    CameraRay out;
    const glm::vec2 offset = pixel_offset(pixel_u, out.weight);
    // The pixel's offset from the image centre, (j - W/2 + 0.5 + dx, -i + H/2 - 0.5 + dy),
    // in scene units on the camera plane.
    const float cx =
        static_cast<float>(px) - 0.5f * static_cast<float>(settings_.width) + 0.5f + offset.x;
    const float cy =
        -static_cast<float>(py) + 0.5f * static_cast<float>(settings_.height) - 0.5f + offset.y;
    Ray& ray = out.ray;
    ray.origin =
        settings_.position + (cx * ortho_pixel_size_.x) * right_ + (cy * ortho_pixel_size_.y) * up_;
    ray.direction = forward_;
    // The direction is the optical axis: depths are distances (so near_clip_mode does not
    // matter here).
    ray.t_min = settings_.near_clip;
    ray.t_max = settings_.far_clip;
    return out;
}

}  // namespace librt
