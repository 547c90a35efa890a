// A sphere in a room rendered over the ranks of an MPI job (run alone it is one rank),
// written by rank 0 to mpi_render.pfm; rank 0 also renders it in one process and fails
// unless the two images are bit-identical.

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/mpi/render_mpi.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>
#include <mpi.h>

#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    int code = 0;
    try {
        librt::Scene scene;
        std::string error;  // each rank builds its scene; all learn if one failed
        try {
            const auto grey = scene.add_material(librt::Material::diffuse({0.8f, 0.8f, 0.8f}));
            scene.add_sphere({{0, -1000, 0}, 990}, grey);  // floor
            scene.add_sphere({{0, 0, 0}, 10}, grey);
            scene.add_sphere_light({{{-12, 28, 20}, 5}, glm::vec3(18.0f)});
            scene.commit();
        } catch (const std::exception& e) {
            error = e.what();
        }
        librt::check_all_ranks(MPI_COMM_WORLD, error);

        librt::CameraSettings view;
        view.width = 48;
        view.height = 32;
        const librt::Camera camera(view);
        librt::PathTracer path_tracer;
        librt::MpiRenderSettings settings;
        settings.render.samples_per_pixel = 4;
        settings.render.threads = 1;
        settings.tile_size = 16;
        const librt::Film film =
            librt::render_mpi(MPI_COMM_WORLD, scene, camera, path_tracer, settings);
        if (rank == 0) {
            const librt::Image image = librt::resolve(film);
            const librt::Image one = librt::render(scene, camera, path_tracer, settings.render);
            if (std::memcmp(image.pixels.data(), one.pixels.data(),
                            image.pixels.size() * sizeof image.pixels[0]) != 0) {
                std::fprintf(stderr, "render_mpi differs from render\n");
                code = 1;
            } else {
                librt::write_pfm("mpi_render.pfm", image);
                std::printf("wrote mpi_render.pfm (%dx%d), identical to a one-process render\n",
                            image.width, image.height);
            }
        }
    } catch (const librt::Error& e) {
        std::fprintf(stderr, "rank %d: %s\n", rank, e.what());
        code = 1;
    }
    MPI_Finalize();
    return code;
}
