#include "light/emission.h"
#include "light/light_bounds.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/light/environment_light.h>
#include <librt/light/scene_summary.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace librt {
namespace {

/// Rec. 709 luminance: what the sampling density follows.
float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// (u, v) in [0, 1)^2 of a unit direction in the light frame (see EnvironmentImage).
glm::vec2 uv_of(const glm::vec3& d) {
    const float theta = std::acos(std::clamp(d.y, -1.0f, 1.0f));
    float phi = std::atan2(-d.z, d.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    return {phi / (2.0f * kPi), theta / kPi};
}

glm::vec3 lookup(const EnvironmentData& data, glm::vec2 uv) {
    const EnvironmentImage& im = data.image;
    if (im.pixels.empty()) return data.constant;
    const int x = std::clamp(int(uv.x * float(im.width)), 0, im.width - 1);
    const int y = std::clamp(int(uv.y * float(im.height)), 0, im.height - 1);
    return im.pixels[std::size_t(y) * std::size_t(im.width) + std::size_t(x)];
}

}  // namespace

EnvironmentLight EnvironmentLight::constant(const glm::vec3& radiance) {
    if (!finite(radiance) || radiance.x < 0.0f || radiance.y < 0.0f || radiance.z < 0.0f) {
        std::ostringstream msg;
        msg << "environment radiance = (" << radiance.x << ", " << radiance.y << ", " << radiance.z
            << "): must be finite and >= 0";
        throw Error(msg.str());
    }
    auto data = std::make_shared<EnvironmentData>();
    data->constant = radiance;
    data->mean_radiance = radiance;
    EnvironmentLight light;
    light.data = std::move(data);
    return light;
}

EnvironmentLight EnvironmentLight::from_image(EnvironmentImage image, const glm::mat3& rotation,
                                              float scale) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
        throw Error("environment image: " + std::to_string(image.width) + " x " +
                    std::to_string(image.height) + " with " + std::to_string(image.pixels.size()) +
                    " pixels");
    const std::size_t w = std::size_t(image.width), h = std::size_t(image.height);
    std::vector<float> weight(w * h);
    glm::dvec3 mean(0.0);
    double solid = 0.0;
    for (std::size_t y = 0; y < h; ++y) {
        // sin(theta) at the row centre: the row's solid angle per unit of (u, v).
        const float s = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (std::size_t x = 0; x < w; ++x) {
            const glm::vec3& c = image.pixels[y * w + x];
            if (!finite(c) || c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) {
                std::ostringstream msg;
                msg << "environment image pixel (" << x << ", " << y << ") = (" << c.x << ", "
                    << c.y << ", " << c.z << "): must be finite and >= 0";
                throw Error(msg.str());
            }
            weight[y * w + x] = luminance(c) * s;
            mean += glm::dvec3(c) * double(s);
            solid += double(s);
        }
    }
    auto data = std::make_shared<EnvironmentData>();
    data->density = Distribution2D(weight, image.width, image.height);
    data->mean_radiance = glm::vec3(mean / std::max(solid, 1e-30));
    data->image = std::move(image);
    EnvironmentLight light;
    light.data = std::move(data);
    light.rotation = rotation;
    light.scale = scale;
    validate(light);
    return light;
}

glm::mat3 rotation_about_up(float degrees) {
    // In double, then rounded: orthonormal to float precision for any angle.
    const double a = double(degrees) * (3.14159265358979323846 / 180.0);
    const float c = float(std::cos(a)), s = float(std::sin(a));
    // Columns: the images of +x, +y and +z.
    return glm::mat3(glm::vec3(c, 0.0f, -s), glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(s, 0.0f, c));
}

void validate(const EnvironmentLight& light) {
    if (!light.data) throw Error("environment light: no data (use constant or from_image)");
    if (!std::isfinite(light.scale) || light.scale < 0.0f) {
        std::ostringstream msg;
        msg << "environment light scale = " << light.scale << ": must be finite and >= 0";
        throw Error(msg.str());
    }
    // Orthonormal: R^T R = I within float rounding.
    const glm::mat3 m = glm::transpose(light.rotation) * light.rotation;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (!(std::fabs(m[i][j] - (i == j ? 1.0f : 0.0f)) < 1e-3f))
                throw Error("environment light rotation: not orthonormal (or not finite)");
}

LightLiSample sample_li(const EnvironmentLight& light, const glm::vec3& ref, glm::vec2 u) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    if (!light.data) return {};
    const EnvironmentData& data = *light.data;
    if (data.image.pixels.empty()) {
        const glm::vec3 d = sample_uniform_sphere(u);
        return {d, data.constant * light.scale, 1.0f / (4.0f * kPi), inf, false};
    }
    const Distribution2D::Sample s = data.density.sample(u);
    const float theta = kPi * s.uv.y, phi = 2.0f * kPi * s.uv.x;
    const float sin_t = std::sin(theta);
    if (!(sin_t > 0.0f) || !(s.pdf > 0.0f)) return {};
    const glm::vec3 local(sin_t * std::cos(phi), std::cos(theta), -sin_t * std::sin(phi));
    // The same density as pdf_li computes from the direction (the same sin(theta) formula,
    // so that the two agree to rounding even near the poles).
    const glm::vec3 wi = glm::normalize(light.rotation * local);
    return {wi, lookup(data, s.uv) * light.scale, pdf_li(light, ref, wi), inf, false};
}

float pdf_li(const EnvironmentLight& light, const glm::vec3& /*ref*/, const glm::vec3& wi) {
    if (!light.data) return 0.0f;
    const EnvironmentData& data = *light.data;
    if (data.image.pixels.empty()) return 1.0f / (4.0f * kPi);
    const glm::vec3 local = glm::transpose(light.rotation) * wi;
    const glm::vec2 uv = uv_of(local);
    const float sin_t = std::sqrt(local.x * local.x + local.z * local.z);
    if (!(sin_t > 0.0f)) return 0.0f;
    // (u, v) density to solid angle: d omega = 2 pi^2 sin(theta) du dv (pbrt 4th ed. 12.5.2).
    const float pdf = data.density.pdf(uv) / (2.0f * kPi * kPi * sin_t);
    return std::isfinite(pdf) ? pdf : 0.0f;
}

glm::vec3 escaped_radiance(const EnvironmentLight& light, const glm::vec3& dir) {
    if (!light.data) return glm::vec3(0.0f);
    if (light.data->image.pixels.empty()) return light.data->constant * light.scale;
    return lookup(*light.data, uv_of(glm::transpose(light.rotation) * dir)) * light.scale;
}

LightLeSample sample_le(const EnvironmentLight& light, const SceneSphere& scene, glm::vec2 u_pos,
                        glm::vec2 u_dir) {
    // Light arriving along wi travels -wi: the same density, the same radiance. The
    // weight L / (pdf_pos pdf_dir) then averages to pi R^2 times the integral of L over
    // the sphere, the power (pbrt 4th ed. 12.5.2, the image light's SampleLe).
    const LightLiSample li = sample_li(light, scene.center, u_dir);
    if (!li.valid()) return {};
    return emission::from_disk(scene, li.wi, li.radiance, li.pdf, u_pos);
}

LightLePdf pdf_le(const EnvironmentLight& light, const SceneSphere& scene,
                  const glm::vec3& /*origin*/, const glm::vec3& /*normal*/,
                  const glm::vec3& direction) {
    return {emission::disk_pdf(scene), pdf_li(light, scene.center, -direction)};
}

glm::vec3 power(const EnvironmentLight& light) {
    if (!light.data) return glm::vec3(0.0f);
    const float r = light.scene_radius > 0.0f ? light.scene_radius : 1.0f;
    // Mean radiance over the sphere times 4 pi sr times pi R^2 m^2.
    return light.data->mean_radiance * (light.scale * 4.0f * kPi * kPi * r * r);
}

LightBounds EnvironmentLight::bounds() const {
    return detail::infinite_light_bounds(power(*this));  // lights from every direction
}

void EnvironmentLight::preprocess(const SceneSummary& scene) { scene_radius = scene.sphere.radius; }

}  // namespace librt
