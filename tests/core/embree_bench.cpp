// Embree reference tracer speed on a random triangle soup: untimed warm-up, then the median of 5 timed runs,
// for closest and any hits. Usage: embree_bench [triangles = 1000000] [rays = 1000000]
#include "renderer/reference/embree_tracer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

using namespace chcrt;

// Process CPU time over all threads: on a shared machine it says what the work cost even when wall-clock time
// includes waiting for other processes.
double cpuSeconds() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

int main(int argc, char** argv) {
    const size_t triangleCount = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
    const size_t rayCount = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1000000;

    // Triangles of size ~0.01 inside [-1, 1]^3 (edge length scaled so that a 1M soup is not opaque).
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    Scene scene;
    scene.name = "random soup";
    const float size = 0.01f * std::cbrt(1e6f / float(triangleCount));
    for (size_t i = 0; i < triangleCount; ++i) {
        const glm::vec3 center(unit(rng), unit(rng), unit(rng));
        const auto base = uint32_t(scene.positions.size());
        for (int k = 0; k < 3; ++k) {
            scene.positions.push_back(center + size * glm::vec3(unit(rng), unit(rng), unit(rng)));
        }
        scene.triangles.emplace_back(base, base + 1, base + 2);
    }
    std::vector<Ray> rays(rayCount);
    for (Ray& ray : rays) {
        ray.origin = 1.5f * glm::vec3(unit(rng), unit(rng), unit(rng));
        const glm::vec3 aim(unit(rng), unit(rng), unit(rng));
        ray.direction = glm::normalize(aim - ray.origin);
        ray.tmin = 0.0f;
        ray.tmax = CHCRT_NO_HIT_T;
    }

    const EmbreeTracer tracer(scene);
    std::printf("%zu triangles, %zu rays, build %.3f s (high quality, robust)\n", triangleCount, rayCount,
                tracer.buildSeconds());
    std::vector<Hit> hits(rayCount);
    for (bool anyHit : {false, true}) {
        tracer.trace(rays, hits, anyHit); // warm-up
        std::vector<double> seconds;
        std::vector<double> cpu;
        for (int run = 0; run < 5; ++run) {
            const auto start = std::chrono::steady_clock::now();
            const double cpuStart = cpuSeconds();
            tracer.trace(rays, hits, anyHit);
            cpu.push_back(cpuSeconds() - cpuStart);
            seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
        std::sort(seconds.begin(), seconds.end());
        std::sort(cpu.begin(), cpu.end());
        const auto hitCount = std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.hit(); });
        std::printf("%-8s median %.4f s (min %.4f, max %.4f) = %.2f Mrays/s; %.2f Mrays per CPU-second; %.1f%% hit\n",
                    anyHit ? "any" : "closest", seconds[2], seconds[0], seconds[4],
                    double(rayCount) / seconds[2] * 1e-6, double(rayCount) / cpu[2] * 1e-6,
                    100.0 * double(hitCount) / double(rayCount));
    }
    return 0;
}
