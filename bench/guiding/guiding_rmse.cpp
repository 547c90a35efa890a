// Path guiding's figures (docs/sampling.md): RMSE against a high-sample unguided
// reference, and efficiency = RMSE^2 x CPU seconds (lower is better; the training passes'
// CPU time is included), guided against unguided, on a room lit only through a gap: its
// one light hangs in a box below the ceiling whose lid has a hole, so the room sees the
// light only as the bright patch the hole throws on the ceiling. A plain program, not
// Google Benchmark: it measures error per time, not speed alone.
//
//   librt_guiding_rmse [--size N] [--ref-spp N] [--threads N] [--hole H] [--spp a,b,c]
//       [--passes P] [--keep 0|1] [--filter 0|1] [--alpha A] [--ref CACHE.pfm]

#include <librt/film/camera.h>
#include <librt/geometry/mesh.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace librt;

namespace {

/// The report's walls and floor as spheres, a diffuse ball, and the lamp box: x, z in
/// [-6, 6] around z = -30, y in [36, 50], its lid holed by a (2 hole) square.
void build_room(Scene& scene, float hole) {
    auto diffuse = [&](glm::vec3 a) { return scene.add_material(Material::diffuse(a)); };
    scene.add_sphere({{0, -1000, 0}, 990}, diffuse({0.8f, 0.8f, 0.8f}));
    scene.add_sphere({{0, 0, -1050}, 940}, diffuse({0.7f, 0.7f, 0.9f}));
    scene.add_sphere({{0, 0, 1000}, 940}, diffuse({0.8f, 0.8f, 0.6f}));
    scene.add_sphere({{1000, 0, 0}, 940}, diffuse({0.8f, 0.2f, 0.2f}));
    scene.add_sphere({{-1000, 0, 0}, 940}, diffuse({0.2f, 0.8f, 0.2f}));
    scene.add_sphere({{0, 1000, 0}, 940}, diffuse({0.9f, 0.9f, 0.9f}));
    scene.add_sphere({{-15, -2, -20}, 8}, diffuse({0.9f, 0.9f, 0.9f}));
    TriangleMesh box;
    const float x0 = -6, x1 = 6, y0 = 36, y1 = 50, z0 = -36, z1 = -24, zc = -30, h = hole;
    box.positions = {{x0, y0, z0},     {x1, y0, z0},    {x1, y0, z1},    {x0, y0, z1},
                     {x0, y1, z0},     {x1, y1, z0},    {x1, y1, z1},    {x0, y1, z1},
                     {-h, y1, zc - h}, {h, y1, zc - h}, {h, y1, zc + h}, {-h, y1, zc + h}};
    box.triangles = {{0, 1, 2},  {0, 2, 3},  {0, 1, 5},  {0, 5, 4},   {3, 2, 6}, {3, 6, 7},
                     {0, 3, 7},  {0, 7, 4},  {1, 2, 6},  {1, 6, 5},   {4, 5, 9}, {4, 9, 8},
                     {5, 6, 10}, {5, 10, 9}, {6, 7, 11}, {6, 11, 10}, {7, 4, 8}, {7, 8, 11}};
    scene.add_mesh(std::move(box), diffuse({0.8f, 0.8f, 0.8f}));
    scene.add_sphere_light({{{0, 42, -30}, 2.5f}, glm::vec3(400.0f)});
    scene.commit();
}

double rmse(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.pixels[i][c]) - double(b.pixels[i][c]);
            sum += d * d;
        }
    return std::sqrt(sum / (3.0 * double(a.pixels.size())));
}

std::vector<int> parse_list(const char* text) {
    std::vector<int> out;
    std::stringstream s(text);
    std::string item;
    while (std::getline(s, item, ',')) out.push_back(std::atoi(item.c_str()));
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    int size = 64, ref_spp = 4096, threads = 2, passes = 5, keep = 1, filter = 0;
    float hole = 3.0f, alpha = 0.7f;
    std::string ref_file;  // cache of the reference (read when it exists, else written)
    std::vector<int> spps{16, 64, 256};
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--size")
            size = std::atoi(argv[i + 1]);
        else if (a == "--ref-spp")
            ref_spp = std::atoi(argv[i + 1]);
        else if (a == "--threads")
            threads = std::atoi(argv[i + 1]);
        else if (a == "--hole")
            hole = float(std::atof(argv[i + 1]));
        else if (a == "--passes")
            passes = std::atoi(argv[i + 1]);
        else if (a == "--keep")
            keep = std::atoi(argv[i + 1]);
        else if (a == "--filter")
            filter = std::atoi(argv[i + 1]);
        else if (a == "--alpha")
            alpha = float(std::atof(argv[i + 1]));
        else if (a == "--ref")
            ref_file = argv[i + 1];
        else if (a == "--spp")
            spps = parse_list(argv[i + 1]);
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 1;
        }
    }
    Scene scene;
    build_room(scene, hole);
    CameraSettings cs;  // the report's view: from (0, 0, 55) down -z, 60 degrees
    cs.width = cs.height = size;
    cs.pixel_jitter = PixelJitter::Gaussian;
    const Camera camera(cs);
    PathTracerSettings base{5, false};

    RenderSettings rs;
    rs.threads = threads;
    rs.samples_per_pixel = ref_spp;
    rs.seed = 1234567;
    // The protocol's figures (docs/sampling.md) predate the Sobol' and adaptive defaults.
    rs.sampler = SamplerKind::Independent;
    rs.adaptive.enabled = false;
    PathTracer ref_tracer(base);
    RenderStats ref_stats;
    Image reference;
    if (!ref_file.empty() && std::ifstream(ref_file).good()) {
        reference = read_pfm(ref_file);
    } else {
        reference = render(scene, camera, ref_tracer, rs, &ref_stats);
        if (!ref_file.empty()) write_pfm(ref_file, reference);
    }
    std::printf("lamp room %dx%d, hole %.1f: reference %d spp unguided, %.1f CPU s\n", size, size,
                double(hole), ref_spp, ref_stats.cpu_seconds);
    std::printf("%-9s %6s %10s %8s %12s\n", "", "spp", "RMSE", "CPU s", "RMSE^2 x s");
    for (const int spp : spps) {
        double eff[2] = {0.0, 0.0};
        for (int guided = 0; guided < 2; ++guided) {
            PathTracerSettings s = base;
            s.guiding.enabled = guided == 1;
            s.guiding.training_passes = passes;
            s.guiding.keep_training_samples = keep != 0;
            s.guiding.filter_records = filter != 0;
            s.guiding.bsdf_fraction = alpha;
            PathTracer tracer(s);
            rs.samples_per_pixel = spp;
            rs.seed = 7;
            RenderStats stats;
            const Image image = render(scene, camera, tracer, rs, &stats);
            const double e = rmse(image, reference);
            eff[guided] = e * e * stats.cpu_seconds;
            std::printf("%-9s %6d %10.5f %8.2f %12.3e\n", guided ? "guided" : "unguided", spp, e,
                        stats.cpu_seconds, eff[guided]);
        }
        std::printf("  efficiency gain %.2fx, RMSE at equal time %.2fx lower\n", eff[0] / eff[1],
                    std::sqrt(eff[0] / eff[1]));
    }
    return 0;
}
