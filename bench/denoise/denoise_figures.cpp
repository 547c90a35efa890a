// The denoiser's figures (issue 38, docs/benchmarks.md): on a scene file or the report's
// synthesis scene, at each sample count, the relMSE of the noisy and of the denoised image
// against a long reference, the largest 16 x 16 block-mean deviation, and the cost of
// denoising next to the render's. A plain program, not Google Benchmark: it measures error.
//
//   librt_denoise_figures SCENE|synthesis [--size WxH] [--spp 16,64] [--ref-spp N]
//       [--threads N] [--light-units watts|photometric]
//
// Each image is rendered as rt_render renders it (the path tracer, 5 bounces, Gaussian
// pixel jitter; the synthesis scene with its lens), in two halves of its samples
// (render_block), then denoised (denoiser_input of the two films). The reference has a
// seed of its own; its own noise, estimated per pixel from its halves, (a - b)^2 / 4, is
// subtracted from each squared error, so a finite reference does not inflate the figures.

#include "common/cli.h"
#include "common/report_scene.h"

#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/loader/scene_file.h>
#include <librt/render/denoiser.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace librt;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Halves {
    Film half;
    Film full;
    double seconds = 0.0;
};

/// Samples [0, spp / 2) onto a film with AOVs, a copy, then [spp / 2, spp).
Halves render_halves(const Scene& scene, const Camera& camera, Integrator& integrator, int spp,
                     std::uint64_t seed, int threads) {
    BlockSettings rs;
    rs.seed = seed;
    rs.threads = threads;
    rs.sampler = SamplerKind::Independent;  // the figures' (measured before Sobol' was the default)
    Halves h;
    const auto t0 = Clock::now();
    h.full = Film(camera.width(), camera.height(), true);
    const auto first = std::uint32_t(spp / 2);
    (void)render_block(scene, camera, integrator, h.full,
                       {0, 0, camera.width(), camera.height(), 0, first}, rs);
    h.half = h.full;
    (void)render_block(scene, camera, integrator, h.full,
                       {0, 0, camera.width(), camera.height(), first, std::uint32_t(spp) - first},
                       rs);
    h.seconds = seconds_since(t0);
    return h;
}

/// relMSE, mean over pixels and channels of ((x - r)^2 - Var r) / (r^2 + 0.01).
double rel_mse(const Image& x, const Image& ref, const std::vector<glm::vec3>& ref_var) {
    double s = 0.0;
    for (std::size_t i = 0; i < x.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double r = ref.pixels[i][c];
            const double d = double(x.pixels[i][c]) - r;
            s += (d * d - double(ref_var[i][c])) / (r * r + 0.01);
        }
    }
    return s / double(3 * x.pixels.size());
}

double luminance(glm::vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

/// One 16 x 16 block (blocks at the image's edge may be smaller): luminance means of the
/// noisy, the denoised and the reference image, and the variances of the noisy and the
/// reference means from their halves (Var of a pixel's mean = s (1 - s) (a - b)^2).
struct Block {
    int x = 0, y = 0;
    double noisy = 0.0, denoised = 0.0, ref = 0.0, var_noisy = 0.0, var_ref = 0.0;
};

std::vector<Block> blocks(const DenoiserInput& in, const Image& out, const DenoiserInput& ref) {
    std::vector<Block> v;
    for (int by = 0; by < out.height; by += 16) {
        for (int bx = 0; bx < out.width; bx += 16) {
            Block b{bx, by};
            int n = 0;
            for (int y = by; y < std::min(by + 16, out.height); ++y) {
                for (int x = bx; x < std::min(bx + 16, out.width); ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(out.width) + std::size_t(x);
                    b.noisy += luminance(in.beauty.pixels[i]);
                    b.denoised += luminance(out.pixels[i]);
                    b.ref += luminance(ref.beauty.pixels[i]);
                    const double s = in.share_a[i], sr = ref.share_a[i];
                    const double d = luminance(in.half_a.pixels[i] - in.half_b.pixels[i]);
                    const double dr = luminance(ref.half_a.pixels[i] - ref.half_b.pixels[i]);
                    b.var_noisy += s * (1.0 - s) * d * d;
                    b.var_ref += sr * (1.0 - sr) * dr * dr;
                    ++n;
                }
            }
            b.noisy /= n;
            b.denoised /= n;
            b.ref /= n;
            b.var_noisy /= double(n) * n;
            b.var_ref /= double(n) * n;
            v.push_back(b);
        }
    }
    return v;
}

/// Blocks darker than 1e-3 of the image's brightest block are left out of the figures.
double dark_floor(const std::vector<Block>& v) {
    double top = 0.0;
    for (const Block& b : v) top = std::max(top, b.ref);
    return 1e-3 * top;
}

/// DENOISE_CACHE=DIR: the renders (deterministic for their seeds) are kept in DIR as raw
/// floats and read back on the next run, so that variants of the denoiser are compared on
/// the same inputs in seconds rather than minutes. Layers in a fixed order, each its width,
/// height and pixels.
void write_input(const std::string& path, const DenoiserInput& in) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) throw std::runtime_error("cannot write " + path);
    const auto layer = [&](const Image& im) {
        const int wh[2] = {im.width, im.height};
        std::fwrite(wh, sizeof wh, 1, f);
        std::fwrite(im.pixels.data(), sizeof(glm::vec3), im.pixels.size(), f);
    };
    for (const Image* im :
         {&in.beauty, &in.albedo, &in.normal, &in.half_a, &in.half_b, &in.albedo_a, &in.albedo_b,
          &in.normal_a, &in.normal_b, &in.emission_a, &in.emission_b})
        layer(*im);
    std::fwrite(in.share_a.data(), sizeof(float), in.share_a.size(), f);
    std::fclose(f);
}

bool read_input(const std::string& path, DenoiserInput& in) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) return false;
    bool ok = true;
    const auto layer = [&](Image& im) {
        int wh[2] = {0, 0};
        ok = ok && std::fread(wh, sizeof wh, 1, f) == 1;
        if (!ok) return;
        im = Image(wh[0], wh[1]);
        ok = std::fread(im.pixels.data(), sizeof(glm::vec3), im.pixels.size(), f) ==
             im.pixels.size();
    };
    for (Image* im : {&in.beauty, &in.albedo, &in.normal, &in.half_a, &in.half_b, &in.albedo_a,
                      &in.albedo_b, &in.normal_a, &in.normal_b, &in.emission_a, &in.emission_b})
        layer(*im);
    in.share_a.resize(in.beauty.pixels.size());
    ok = ok &&
         std::fread(in.share_a.data(), sizeof(float), in.share_a.size(), f) == in.share_a.size();
    std::fclose(f);
    return ok;
}

/// The input rendered with `seed` at `spp`, from DENOISE_CACHE when it is there.
template <class Render>
DenoiserInput cached_input(const std::string& key, Render render, double& seconds) {
    const char* dir = std::getenv("DENOISE_CACHE");
    DenoiserInput in;
    const std::string path = dir != nullptr ? std::string(dir) + "/" + key + ".bin" : "";
    if (dir != nullptr && read_input(path, in)) return in;
    const Halves h = render();
    seconds = h.seconds;
    in = denoiser_input(h.half, h.full);
    if (dir != nullptr) write_input(path, in);
    return in;
}

std::vector<int> parse_list(const std::string& text) {
    std::vector<int> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(std::atoi(item.c_str()));
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: librt_denoise_figures SCENE|synthesis [--size WxH] [--spp 16,64] "
                     "[--ref-spp N] [--threads N] [--light-units watts|photometric]\n");
        return 1;
    }
    const std::string what = argv[1];
    int width = 320, height = 240, ref_spp = 1024, threads = 0;
    bool photometric = false;
    std::vector<int> spps{16, 64};
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--size") {
            (void)std::sscanf(argv[i + 1], "%dx%d", &width, &height);
        } else if (a == "--spp") {
            spps = parse_list(argv[i + 1]);
        } else if (a == "--ref-spp") {
            ref_spp = std::atoi(argv[i + 1]);
        } else if (a == "--light-units") {
            photometric = std::strcmp(argv[i + 1], "photometric") == 0;
        } else if (a == "--threads") {
            threads = std::atoi(argv[i + 1]);
        } else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 1;
        }
    }
    try {
        Scene scene;
        CameraSettings cs;
        std::unique_ptr<PathTracer> integrator;
        if (what == "synthesis") {
            // rt_synthesis's scene and camera (its lens too), at this size.
            apps::AppOptions options;
            options.width = width;
            options.height = height;
            cs = apps::camera_of(options);
            cs.pixel_jitter = PixelJitter::Gaussian;
            cs.lens = LensModel::Gaussian;
            cs.lens_sigma = 1.0f;
            cs.focal_distance = 55.0f;
            apps::add_room(scene);
            apps::add_report_spheres(scene);
            apps::add_report_mesh(
                scene, apps::load_report_mesh("", apps::placement_of(apps::MeshOptions{})),
                Material::diffuse({0.9f, 0.6f, 0.3f}));
            apps::add_report_light(scene, apps::LightKind::Sphere, options.power);
            scene.commit();
            integrator = std::make_unique<PathTracer>(apps::path_tracer_settings(options));
        } else {
            SceneFileOptions fo;
            fo.width = width;
            fo.height = height;
            // The files' own lights, as the figures in docs/benchmarks.md were measured
            // (cornell_pbr.glb, lit by its panel alone, would get the studio lighting).
            fo.default_lighting = false;
            if (photometric) fo.light_units = PunctualLightUnits::Photometric;
            LoadedScene loaded = load_scene_file(what, fo);
            scene = std::move(loaded.scene);
            scene.commit();
            cs = loaded.camera;
            cs.pixel_jitter = PixelJitter::Gaussian;  // as rt_render
            PathTracerSettings pt;
            pt.max_depth = 5;  // rt_render's default
            integrator = std::make_unique<PathTracer>(pt);
        }
        const Camera camera(cs);
        integrator->preprocess(scene);
        const std::string base = what.substr(what.find_last_of('/') + 1) +
                                 (photometric ? "_photometric" : "") + "_" + std::to_string(width) +
                                 "x" + std::to_string(height);
        double ref_seconds = 0.0;
        const DenoiserInput ref_in = cached_input(
            base + "_ref" + std::to_string(ref_spp),
            [&] { return render_halves(scene, camera, *integrator, ref_spp, 1000003, threads); },
            ref_seconds);
        std::vector<glm::vec3> ref_var(ref_in.beauty.pixels.size());
        for (std::size_t i = 0; i < ref_var.size(); ++i) {
            const glm::vec3 d = ref_in.half_a.pixels[i] - ref_in.half_b.pixels[i];
            ref_var[i] = d * d * 0.25f;
        }
        std::printf("# %s %dx%d, reference %d spp (%.1f s)\n", what.c_str(), camera.width(),
                    camera.height(), ref_spp, ref_seconds);
        for (const int spp : spps) {
            double render_seconds = 0.0;
            const DenoiserInput in = cached_input(
                base + "_" + std::to_string(spp),
                [&] { return render_halves(scene, camera, *integrator, spp, 1, threads); },
                render_seconds);
            DenoiserSettings ds;
            ds.threads = threads;
            // Settings to try without a rebuild (the figures in docs/benchmarks.md use none).
            if (const char* v = std::getenv("DENOISE_NORMAL_SIGMA")) ds.normal_sigma = std::stof(v);
            if (const char* v = std::getenv("DENOISE_ALBEDO_SIGMA")) ds.albedo_sigma = std::stof(v);
            if (const char* v = std::getenv("DENOISE_STRENGTH")) ds.strength = std::stof(v);
            if (const char* v = std::getenv("DENOISE_RADIUS")) ds.radius = std::stoi(v);
            if (const char* v = std::getenv("DENOISE_PATCH")) ds.patch_radius = std::stoi(v);
            if (const char* v = std::getenv("DENOISE_MAX_SE"))
                ds.max_standard_errors = std::stof(v);
            const auto t0 = Clock::now();
            const Image out = denoise(in, ds);
            const double denoise_seconds = seconds_since(t0);
            const double noisy = rel_mse(in.beauty, ref_in.beauty, ref_var);
            const double den = rel_mse(out, ref_in.beauty, ref_var);
            // Block means: the worst |x / ref - 1| of the noisy and the denoised image; the
            // worst the denoiser moved a block (|denoised - noisy| / ref: what the filter
            // adds to the render's own error); and how many blocks miss 1 % plus 4 standard
            // errors of the noisy and the reference block means (the render's noise).
            const std::vector<Block> bl = blocks(in, out, ref_in);
            const double floor = dark_floor(bl);
            double worst_noisy = 0.0, worst_den = 0.0, worst_moved = 0.0;
            int off = 0, counted = 0;
            for (const Block& b : bl) {
                if (b.ref <= floor) continue;
                ++counted;
                worst_noisy = std::max(worst_noisy, std::abs(b.noisy / b.ref - 1.0));
                worst_den = std::max(worst_den, std::abs(b.denoised / b.ref - 1.0));
                worst_moved = std::max(worst_moved, std::abs(b.denoised - b.noisy) / b.ref);
                const double allowed = 0.01 * b.ref + 4.0 * std::sqrt(b.var_noisy + b.var_ref);
                if (std::abs(b.denoised - b.ref) > allowed) {
                    ++off;
                    if (std::getenv("DENOISE_BLOCKS") != nullptr) {
                        std::printf(
                            "  block (%d, %d) ref %.4g: noisy %+.2f %%, denoised %+.2f "
                            "%%, moved %+.2f %%, 4 sigma %.2f %% (ref's %.2f %%)\n",
                            b.x, b.y, b.ref, 100.0 * (b.noisy / b.ref - 1.0),
                            100.0 * (b.denoised / b.ref - 1.0),
                            100.0 * (b.denoised - b.noisy) / b.ref,
                            400.0 * std::sqrt(b.var_noisy + b.var_ref) / b.ref,
                            400.0 * std::sqrt(b.var_ref) / b.ref);
                    }
                }
            }
            if (std::getenv("DENOISE_DUMP") != nullptr) {
                const std::string prefix = std::getenv("DENOISE_DUMP") + std::to_string(spp);
                write_image(prefix + "_noisy.pfm", in.beauty, ToneMap{1.0f, 1.0f});
                write_image(prefix + "_denoised.pfm", out, ToneMap{1.0f, 1.0f});
                write_image(prefix + "_ref.pfm", ref_in.beauty, ToneMap{1.0f, 1.0f});
            }
            std::printf(
                "| %s | %d | %.4g | %.4g | %.1fx | %.2f %% | %.2f %% | %.2f %% | %d / %d "
                "| %.2f s | %.2f s |\n",
                what.c_str(), spp, noisy, den, noisy / den, 100.0 * worst_noisy, 100.0 * worst_den,
                100.0 * worst_moved, off, counted, render_seconds, denoise_seconds);
            std::fflush(stdout);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", what.c_str(), e.what());
        return 1;
    }
    return 0;
}
