// Thread scaling of the render loop: renders a scene with 1, 2, 4, ... threads (up to the
// machine's cores), reports wall time, samples/s and the speed-up over one thread, and checks
// that every film is bit-identical to the one-thread film. Writes no image, so it links no image
// library and can be carried to another machine with only Embree and TBB beside it.
//
//   penumbra_thread_scaling SCENE [--spp N] [--res WxH] [--repeat R] [--max-threads T]
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"

using namespace penumbra;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE [--spp N] [--res WxH] [--repeat R] [--max-threads T]\n",
                     argv[0]);
        return 2;
    }
    try {
        Scene scene = loadScene(argv[1]);
        int repeat = 3, maxThreads = tbb::info::default_concurrency();
        for (int i = 2; i + 1 < argc; i += 2) {
            const std::string option = argv[i], value = argv[i + 1];
            if (option == "--spp")
                scene.film.samplesPerPixel = std::stoi(value);
            else if (option == "--res")
                std::sscanf(value.c_str(), "%dx%d", &scene.film.width, &scene.film.height);
            else if (option == "--repeat")
                repeat = std::stoi(value);
            else if (option == "--max-threads")
                maxThreads = std::stoi(value);
            else
                throw InputError("unknown option " + option);
        }
        std::vector<int> threadCounts;
        for (int t = 1; t < maxThreads; t *= 2) threadCounts.push_back(t);
        threadCounts.push_back(maxThreads);

        std::printf("scene %s, %dx%d, %d spp, best of %d\n", argv[1], scene.film.width, scene.film.height,
                    scene.film.samplesPerPixel, repeat);
        std::printf(
            "| threads | seconds | M samples/s | M rays/s | speed-up | same image "
            "|\n|---|---|---|---|---|---|\n");
        Film reference(scene.film.width, scene.film.height);
        double oneThreadSeconds = 0;
        for (int threads : threadCounts) {
            double best = 1e300;
            RenderStats stats;
            Film film(scene.film.width, scene.film.height);
            for (int r = 0; r < repeat; ++r) {
                film = Film(scene.film.width, scene.film.height);
                RenderOptions options;
                options.threads = threads;
                stats = render(scene, options, film);
                best = std::min(best, stats.renderSeconds);
            }
            if (threads == 1) {
                reference = film;
                oneThreadSeconds = best;
            }
            bool same = true;
            for (int y = 0; y < film.height() && same; ++y)
                for (int x = 0; x < film.width() && same; ++x) same = film.at(x, y) == reference.at(x, y);
            std::printf("| %d | %.3f | %.2f | %.2f | %.2fx | %s |\n", threads, best,
                        stats.samples / best * 1e-6, stats.rays.total() / best * 1e-6,
                        oneThreadSeconds / best, same ? "yes" : "NO");
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_thread_scaling: error: %s\n", e.what());
        return 1;
    }
}
