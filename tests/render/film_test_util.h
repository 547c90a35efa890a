#pragma once

// A small scene with every material kind (diffuse, textured-free mirror and glass, a
// sphere light, a glowing diffuse), a jittered camera with depth of field and a path
// tracer, shared by the film, progressive and EXR tests.

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/scene/scene.h>

#include <cmath>
#include <cstring>

namespace librt::testing {

inline Scene film_test_scene() {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.8f, 0.7f, 0.6f)));
    const auto red = scene.add_material(Material::diffuse(glm::vec3(0.7f, 0.1f, 0.1f)));
    const auto chrome = scene.add_material(Material::mirror(glm::vec3(0.9f)));
    const auto glass = scene.add_material(Material::dielectric(1.5f));
    (void)scene.add_sphere(Sphere{{0.0f, -1000.0f, 0.0f}, 999.0f}, white);  // floor at y = -1
    (void)scene.add_sphere(Sphere{{-1.2f, 0.0f, 0.0f}, 0.8f}, chrome);
    (void)scene.add_sphere(Sphere{{1.2f, 0.0f, 0.5f}, 0.7f}, glass);
    (void)scene.add_mesh(make_box({-0.4f, -1.0f, -1.5f}, {0.4f, 0.6f, -0.7f}), red);
    (void)scene.add_sphere_light({{{0.0f, 3.0f, 1.0f}, 0.5f}, glm::vec3(20.0f)});
    scene.commit();
    return scene;
}

/// The path tracer's samples scaled by 2^k, k uniform in [-40, 40): a double holds 53
/// bits, so summing floats of a few binades is exact in any order, and only samples this
/// far apart make the order of additions show in the bits. The split-render tests use it
/// so that a wrong summation order would fail them.
class WideRangeIntegrator final : public Integrator {
public:
    void preprocess(const Scene& scene) override { inner_.preprocess(scene); }
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray,
                               Sampler& sampler) const override {
        const float k = std::floor(80.0f * sampler.next_1d()) - 40.0f;
        return inner_.li(scene, ray, sampler) * std::exp2(k);
    }

private:
    PathTracer inner_{PathTracerSettings{4, false}};
};

inline Camera film_test_camera(int width = 29, int height = 19) {
    CameraSettings cs;
    cs.position = {0.0f, 0.5f, 6.0f};
    cs.look_at = {0.0f, 0.0f, 0.0f};
    cs.width = width;
    cs.height = height;
    cs.vertical_fov_degrees = 40.0f;
    cs.pixel_jitter = PixelJitter::Gaussian;
    cs.lens = LensModel::Disk;
    cs.lens_radius = 0.05f;
    cs.focal_distance = 6.0f;
    return Camera(cs);
}

/// True when the two films hold the same records, byte for byte.
inline bool same_records(const Film& a, const Film& b) {
    return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
           a.aovs.size() == b.aovs.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(FilmPixel)) ==
               0 &&
           (a.aovs.empty() ||
            std::memcmp(a.aovs.data(), b.aovs.data(), a.aovs.size() * sizeof(AovPixel)) == 0);
}

/// True when the two images hold the same floats, byte for byte.
inline bool same_pixels(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

}  // namespace librt::testing
