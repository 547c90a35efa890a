// Kevin Beason's smallpt Cornell box (nine spheres; walls of radius 1e5; a radius-600
// light sphere of which an 18-unit cap pokes through the ceiling), rebuilt through librt's
// public API, for issue 15's efficiency comparison (bench/smallpt/efficiency.sh). The scene
// data are smallpt's published numbers; the camera is smallpt's (eye (50, 52, 295.6),
// direction (0, -0.042612, -1), a vertical extent of 0.5135 at unit depth, rays starting
// 140 units in front: a near clip plane).
//
// Usage:
//   librt_smallpt render SPP SAMPLER LIGHT OUT.pfm [THREADS=1] [SEED=1] [WIDTH=256 HEIGHT=192]
//       SAMPLER: independent | sobol, optionally +guiding[:PASSES] (path guiding, the
//       training passes kept in the image), +nokeep, +nofilter, +alpha=A; LIGHT: mis (the light
//       sphere light-sampled, MIS), bounded (the same with LightChoice::Bounded), emitter (the
//       sphere only an emitter found by BSDF sampling, as smallpt finds it). Tent filter of
//       radius 1. Prints "cpu_seconds S" and "wall_seconds S".
//   librt_smallpt rmse A.pfm REFERENCE.pfm
//       Prints the RMSE over all pixels and channels.

#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

using namespace librt;

enum class LightMode { Mis, Bounded, Emitter };

void build_scene(Scene& scene, LightMode mode) {
    const auto diffuse = [&](glm::vec3 c) { return scene.add_material(Material::diffuse(c)); };
    // The walls in double: smallpt's centres -1e5 + 81.6 and 1e5 + 1 are not floats.
    scene.add_sphere(glm::dvec3(1e5 + 1, 40.8, 81.6), 1e5, diffuse({0.75f, 0.25f, 0.25f}));  // left
    scene.add_sphere(glm::dvec3(-1e5 + 99, 40.8, 81.6), 1e5,
                     diffuse({0.25f, 0.25f, 0.75f}));                                     // right
    scene.add_sphere(glm::dvec3(50, 40.8, 1e5), 1e5, diffuse(glm::vec3(0.75f)));          // back
    scene.add_sphere(glm::dvec3(50, 40.8, -1e5 + 170), 1e5, diffuse(glm::vec3(0.0f)));    // front
    scene.add_sphere(glm::dvec3(50, 1e5, 81.6), 1e5, diffuse(glm::vec3(0.75f)));          // floor
    scene.add_sphere(glm::dvec3(50, -1e5 + 81.6, 81.6), 1e5, diffuse(glm::vec3(0.75f)));  // ceiling
    scene.add_sphere(glm::dvec3(27, 16.5, 47), 16.5,
                     scene.add_material(Material::mirror(glm::vec3(0.999f))));
    scene.add_sphere(glm::dvec3(73, 16.5, 78), 16.5,
                     scene.add_material(Material::dielectric(1.5f, true, glm::vec3(0.999f))));
    const glm::dvec3 light_centre(50, 681.6 - 0.27, 81.6);
    const glm::vec3 le(12.0f);
    if (mode == LightMode::Emitter) {
        scene.add_sphere(light_centre, 600.0, scene.add_material(Material::emissive(le)));
    } else {
        (void)scene.add_sphere_light(SphereLight{Sphere{glm::vec3(light_centre), 600.0f}, le});
    }
    scene.commit();
}

CameraSettings smallpt_camera(int width, int height) {
    CameraSettings s;
    s.position = {50.0f, 52.0f, 295.6f};
    s.look_at = s.position + glm::normalize(glm::vec3(0.0f, -0.042612f, -1.0f));
    // smallpt spans 0.5135 vertically at unit depth: fov = 2 atan(0.5135 / 2).
    s.vertical_fov_degrees = float(2.0 * std::atan(0.5135 / 2.0) * 180.0 / kPiDouble);
    s.width = width;
    s.height = height;
    s.near_clip = 140.0f;
    s.pixel_jitter = PixelJitter::Filter;
    s.pixel_filter.kind = FilterKind::Tent;
    s.pixel_filter.radius = 1.0f;
    return s;
}

int render_command(int argc, char** argv) {
    if (argc < 6) {
        std::fprintf(stderr,
                     "usage: librt_smallpt render SPP SAMPLER LIGHT OUT.pfm [THREADS] "
                     "[SEED] [WIDTH HEIGHT]\n");
        return 2;
    }
    const int spp = std::atoi(argv[2]);
    // SAMPLER[+guiding[:PASSES]][+nokeep][+nofilter][+alpha=A]: path guiding, its
    // training passes (default 5) kept in the image unless +nokeep, records filtered
    // unless +nofilter, BSDF fraction A (default: GuidingSettings::bsdf_fraction).
    std::string sampler = argv[3];
    const std::string light = argv[4];
    PathTracerSettings pts;
    for (std::size_t plus = sampler.find('+'); plus != std::string::npos;
         plus = sampler.find('+')) {
        const std::size_t end = sampler.find('+', plus + 1);
        const std::string opt =
            sampler.substr(plus + 1, end == std::string::npos ? std::string::npos : end - plus - 1);
        sampler.erase(plus, opt.size() + 1);
        if (opt.rfind("guiding", 0) == 0) {
            pts.guiding.enabled = true;
            pts.guiding.keep_training_samples = true;
            if (opt.size() > 8) pts.guiding.training_passes = std::atoi(opt.c_str() + 8);
        } else if (opt == "nokeep") {
            pts.guiding.keep_training_samples = false;
        } else if (opt == "nofilter") {
            pts.guiding.filter_records = false;
        } else if (opt.rfind("alpha=", 0) == 0) {
            pts.guiding.bsdf_fraction = std::strtof(opt.c_str() + 6, nullptr);
        } else {
            throw Error("SAMPLER option +" + opt +
                        ": must be guiding[:N], nokeep, nofilter or alpha=A");
        }
    }
    const std::string out = argv[5];
    const int threads = argc > 6 ? std::atoi(argv[6]) : 1;
    const auto seed = std::uint64_t(argc > 7 ? std::atoll(argv[7]) : 1);
    const int width = argc > 9 ? std::atoi(argv[8]) : 256;
    const int height = argc > 9 ? std::atoi(argv[9]) : 192;
    const LightMode mode =
        light == "emitter"   ? LightMode::Emitter
        : light == "bounded" ? LightMode::Bounded
        : light == "mis"     ? LightMode::Mis
                         : throw Error("LIGHT = " + light + ": must be mis, bounded or emitter");
    Scene scene;
    build_scene(scene, mode);
    const Camera camera(smallpt_camera(width, height));
    // The library's defaults: unbounded depth with roulette from bounce 3, MIS.
    pts.light_choice = mode == LightMode::Bounded ? LightChoice::Bounded : LightChoice::Power;
    PathTracer integrator(pts);
    RenderSettings rs;
    rs.samples_per_pixel = spp;
    rs.threads = threads;
    rs.seed = seed;
    rs.adaptive.enabled =
        false;  // the protocol's uniform samples (its figures predate the default)
    rs.sampler = SamplerKind::Independent;
    if (sampler == "sobol")
        rs.sampler = SamplerKind::Sobol;
    else if (sampler != "independent")
        throw Error("SAMPLER = " + sampler + ": must be independent or sobol");
    RenderStats stats;
    const Image image = render(scene, camera, integrator, rs, &stats);
    write_pfm(out, image);
    std::printf("cpu_seconds %.4f\nwall_seconds %.4f\n", stats.cpu_seconds, stats.seconds);
    if (pts.guiding.enabled)
        std::printf("guiding_leaves %zu\ntraining_passes %d\n", integrator.guiding_leaf_count(),
                    stats.training_passes);
    return 0;
}

int rmse_command(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: librt_smallpt rmse A.pfm REFERENCE.pfm\n");
        return 2;
    }
    const Image a = read_pfm(argv[2]), b = read_pfm(argv[3]);
    if (a.width != b.width || a.height != b.height)
        throw Error(std::string(argv[2]) + " and " + argv[3] + ": sizes differ");
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const glm::dvec3 d = glm::dvec3(a.at(x, y)) - glm::dvec3(b.at(x, y));
            sum += glm::dot(d, d);
        }
    // Root mean square over pixels and channels.
    std::printf("%.8g\n", std::sqrt(sum / (3.0 * double(a.width) * double(a.height))));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::string cmd = argc > 1 ? argv[1] : "";
        if (cmd == "render") return render_command(argc, argv);
        if (cmd == "rmse") return rmse_command(argc, argv);
        std::fprintf(stderr, "usage: librt_smallpt render ... | rmse ...\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "librt_smallpt: %s\n", e.what());
        return 1;
    }
}
