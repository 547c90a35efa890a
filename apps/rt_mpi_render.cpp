// The report's synthesis image rendered over the ranks of an MPI job (librt::mpi):
//   mpirun -np 4 --hostfile hosts rt_mpi_render --size 1024 --spp 256 -o synthesis.exr
// Every rank builds the scene itself; rank 0 hands out tiles, gathers them and writes the
// image, byte-identical to a one-process render with the same seed and settings
// (--single-process renders that reference without MPI scheduling). Runs without mpirun
// too, as one rank. See docs/distributed.md.
#include "common/cli.h"
#include "common/output_image.h"

#include <librt/accel/simd.h>
#include <librt/core/error.h>
#include <librt/core/tone_map.h>
#include <librt/integrator/integrators.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>
#include <librt/mpi/render_mpi.h>
#include <librt/mpi/same_job.h>
#include <librt/render/renderer.h>

#include <CLI/CLI.hpp>
#include <mpi.h>
#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

using namespace librt;

namespace {

std::atomic<bool> g_cancel{false};
extern "C" void on_signal(int) { g_cancel = true; }

// --fail-rank: how the chosen rank fails, for the failure tests (docs/distributed.md).
enum class FailHow { Setup, Render, Kill };

// Wraps the path tracer so that one rank fails part-way through its share of the frame:
// after `after` samples it throws (FailHow::Render) or kills its own process (Kill).
class FailingIntegrator final : public Integrator {
public:
    FailingIntegrator(Integrator& inner, FailHow how, long long after)
        : inner_(inner), how_(how), after_(after) {}
    void preprocess(const Scene& scene) override { inner_.preprocess(scene); }
    [[nodiscard]] std::uint32_t begin_training_pass(int pass) override {
        return inner_.begin_training_pass(pass);
    }
    void end_training_pass(int pass) override { inner_.end_training_pass(pass); }
    [[nodiscard]] bool keeps_training_samples() const override {
        return inner_.keeps_training_samples();
    }
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray,
                               Sampler& sampler) const override {
        if (calls_.fetch_add(1) == after_) {
            if (how_ == FailHow::Kill) std::raise(SIGKILL);
            throw Error("--fail-rank: simulated failure after " + std::to_string(after_) +
                        " samples");
        }
        return inner_.li(scene, ray, sampler);
    }

private:
    Integrator& inner_;
    FailHow how_;
    long long after_;
    mutable std::atomic<long long> calls_{0};
};

// CPU seconds (user + system) this process has used so far.
double cpu_seconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int rank = 0;
    int size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);

    CLI::App app{"The report's synthesis image over the ranks of an MPI job", "rt_mpi_render"};
    apps::AppOptions options;
    options.spp = 80;
    options.output = "synthesis.exr";
    apps::add_common_options(app, options);
    app.get_option("--output")->description("Output image: .exr (every layer), .png, .pfm or .hdr");
    app.get_option("--threads")->description("Worker threads per rank, 0 = all cores");
    int tile = 32;
    bool single = false;
    bool exr_float = false;  // the default now; accepted so that older command lines run
    bool exr_half = false;
    bool root_schedules_only = false;
    int fail_rank = -1;
    FailHow fail_how = FailHow::Render;
    long long fail_after = 2000;
    app.add_option("--tile", tile, "Side of the tiles rank 0 hands out")->capture_default_str();
    app.add_flag("--single-process", single,
                 "Render in this process with librt::render_block, no MPI scheduling (the "
                 "reference the MPI render equals byte for byte)");
    app.add_flag("--exr-float", exr_float, "EXR channels as 32-bit float (the default)");
    app.add_flag("--exr-half", exr_half,
                 "EXR beauty, albedo and normal as 16-bit half (values above 65504 clamped to "
                 "it, with a warning)");
    app.add_flag("--root-schedules-only", root_schedules_only,
                 "Rank 0 only schedules and gathers, rendering nothing");
    app.add_option("--fail-rank", fail_rank, "Test only: make this rank fail");
    app.add_option("--fail-how", fail_how,
                   "Test only: setup (bad mesh file), render (throws) or kill")
        ->transform(CLI::CheckedTransformer(
            std::map<std::string, FailHow>{
                {"setup", FailHow::Setup}, {"render", FailHow::Render}, {"kill", FailHow::Kill}},
            CLI::ignore_case));
    app.add_option("--fail-after", fail_after, "Test only: samples the failing rank takes first")
        ->capture_default_str();

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Every rank parsed the same line; one of them speaks. Exit 1 for a bad command
        // line, 0 for --help (not CLI11's own codes), as apps::run.
        const int code = rank == 0 ? app.exit(e) : e.get_exit_code();
        MPI_Finalize();
        return code == 0 ? 0 : 1;
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const std::string who = "rt_mpi_render: rank " + std::to_string(rank) + ": ";
    // A refused LIBRT_SIMD (every rank reads the same environment): rank 0 says it.
    if (rank == 0 && !librt::simd_path_note().empty())
        std::cerr << who << librt::simd_path_note() << '\n';

    int code = 0;
    try {
        const ToneMap tone{options.exposure * kReportExposure, 0.45f};
        validate(tone);
        // Each rank builds the scene; a failure on any rank stops all before rendering.
        Scene scene;
        std::string setup_error;
        try {
            // Rank 0 writes: its output is checked first (a temporary created and removed),
            // so an unwritable -o stops every rank before the scene is built.
            if (rank == 0) check_image_path(options.output);
            apps::add_room(scene);
            apps::add_report_spheres(scene);
            const bool fail_here = rank == fail_rank && fail_how == FailHow::Setup;
            apps::add_report_mesh(
                scene,
                apps::load_report_mesh(fail_here ? "/nonexistent/rt_mpi_render_fail.obj" : "",
                                       apps::MeshPlacement{}),
                Material::diffuse({0.9f, 0.6f, 0.3f}));
            apps::add_report_light(scene, apps::LightKind::Sphere, options.power);
            scene.commit();
        } catch (const std::exception& e) {
            setup_error = e.what();
        }
        if (!single) check_all_ranks(MPI_COMM_WORLD, setup_error);
        if (!setup_error.empty()) throw Error(setup_error);
        // Every rank was given the same options (the scene is built in code from them): each
        // option as typed, or "(default)". Not --threads and --quiet, which may differ.
        if (!single) {
            std::vector<JobItem> items;
            for (const CLI::Option* option : app.get_options()) {
                const std::string name = option->get_name();
                if (name == "--help" || name == "--threads" || name == "--quiet") continue;
                std::string value = option->count() == 0 ? "(default)" : "";
                for (const std::string& r : option->results())
                    value += (value.empty() ? "" : " ") + r;
                items.push_back({name, value});
            }
            check_same_job(MPI_COMM_WORLD, items);
        }

        PathTracer tracer(apps::path_tracer_settings(options));
        FailingIntegrator failing(tracer, fail_how, fail_after);
        Integrator& integrator = rank == fail_rank ? static_cast<Integrator&>(failing)
                                                   : static_cast<Integrator&>(tracer);
        CameraSettings camera_settings = apps::camera_of(options);
        camera_settings.pixel_jitter = PixelJitter::Gaussian;
        camera_settings.lens = LensModel::Gaussian;
        camera_settings.lens_sigma = 1.0f;  // rt_synthesis's defaults
        camera_settings.focal_distance = 55.0f;
        const Camera camera(apps::with_filter(camera_settings, options));

        MpiRenderSettings settings;
        settings.render.samples_per_pixel = options.spp;
        settings.render.threads = options.threads;
        settings.render.seed = options.seed;
        settings.render.sampler = apps::sampler_kind(options);
        settings.render.adaptive.enabled = options.adaptive;
        settings.render.cancel = &g_cancel;
        settings.tile_size = tile;
        settings.aovs = lower_extension(options.output) == ".exr";
        settings.root_renders = !root_schedules_only;

        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = cpu_seconds();
        Film film;
        Image image;
        MpiRenderStats stats;
        if (single) {
            if (rank != 0) throw Error("--single-process runs without mpirun (one rank)");
            validate(settings);
            film = Film(camera.width(), camera.height(), settings.aovs);
            if (settings.render.adaptive.enabled) {
                // render() onto the film: the pilot, the counts, the rest (it keeps no
                // training passes then, as render_mpi does not).
                const RenderStats rs = render(scene, camera, integrator, film, settings.render);
                stats.cancelled = rs.cancelled;
                image = resolve(film);
            } else {
                integrator.preprocess(scene);
                // --guiding keeps its training passes: render the halves apart, as render() does.
                PassCombination kept;
                train(scene, camera, integrator, settings.render, &kept);
                const auto spp = static_cast<std::uint32_t>(options.spp);
                const std::uint32_t mid = kept.count() > 0 ? spp / 2 : 0;
                RenderStats rs =
                    render_block(scene, camera, integrator, film,
                                 {0, 0, film.width, film.height, 0, mid}, settings.render.block());
                Film half = film;
                if (!rs.cancelled) {
                    rs = render_block(scene, camera, integrator, film,
                                      {0, 0, film.width, film.height, mid, spp - mid},
                                      settings.render.block());
                }
                stats.cancelled = rs.cancelled;
                image = kept.combined(half, film);
            }
        } else {
            film = render_mpi(MPI_COMM_WORLD, scene, camera, integrator, settings, &stats, &image);
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // The render's CPU time over all ranks: what MPI costs beside the rendering itself.
        const double cpu_mine = cpu_seconds() - cpu_start;
        double cpu_all = cpu_mine;
        if (!single) MPI_Reduce(&cpu_mine, &cpu_all, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        if (stats.cancelled || g_cancel.load()) {
            if (rank == 0) std::fprintf(stderr, "interrupted: nothing written\n");
            code = 130;
        } else if (rank == 0) {
            apps::OutputLook look = apps::report_look(options.exposure);
            look.exr_half = exr_half && !exr_float;
            apps::write_output(options.output, image, look, &film);
            if (!options.quiet) {
                std::printf("%dx%d, %d spp, %d rank%s x %d threads: %.3f s\n", film.width,
                            film.height, options.spp, size, size == 1 ? "" : "s", options.threads,
                            seconds);
                std::printf("render cpu: %.3f s over all ranks\n", cpu_all);
                if (!single) {
                    std::printf("tiles: %d of %dx%d px; per rank:", stats.tiles, tile, tile);
                    for (const int n : stats.tiles_per_rank) std::printf(" %d", n);
                    std::printf("\ngather: %llu bytes received, %.4f s receiving and copying\n",
                                static_cast<unsigned long long>(stats.gather_bytes),
                                stats.gather_seconds);
                }
                std::printf("wrote %s\n", options.output.c_str());
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s%s\n", who.c_str(), e.what());
        code = 1;
    }
    MPI_Finalize();
    return code;
}
