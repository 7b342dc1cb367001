// BVH build and CPU tracing speed (not a test; no assertions). For each scene: one untimed warm-up build,
// then the median of `runs` timed builds (BvhStats::buildSeconds: from buildBvh's entry to its return,
// statistics included). Tracing: traceCpu over random rays after one untimed pass, validated against brute
// force on a sample before its speed is printed.
//
//   build-bvh/bin/bvh_bench            1M and 5M soups and heightfields, 1 and all threads
//   build-bvh/bin/bvh_bench --quick    small sizes (smoke run)
//   build-bvh/bin/bvh_bench --large    adds a 10M soup (peak memory)
//   build-bvh/bin/bvh_bench --profile  1M soup on one thread only (for perf record)
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/cpu_tracer.h"
#include "tests/bvh/bvh_test_scenes.h"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

namespace {

using namespace chcrt;

double peakRssMegabytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

// CPU time of the whole process (all threads): with other jobs on the machine, wall time alone misleads.
double processCpuSeconds() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

void benchBuild(const Scene& scene, const char* label, uint32_t threads, int runs) {
    BvhBuildOptions options;
    options.threads = threads;
    (void)buildBvh(scene, options); // warm-up: page faults of the first allocation, thread start-up
    std::vector<double> seconds;
    std::vector<double> cpuSeconds;
    Bvh bvh;
    for (int i = 0; i < runs; ++i) {
        bvh = Bvh{};
        const double cpuStart = processCpuSeconds();
        bvh = buildBvh(scene, options);
        cpuSeconds.push_back(processCpuSeconds() - cpuStart);
        seconds.push_back(bvh.stats.buildSeconds);
    }
    std::sort(seconds.begin(), seconds.end());
    std::sort(cpuSeconds.begin(), cpuSeconds.end());
    const double median = seconds[seconds.size() / 2];
    const double triangles = double(scene.triangles.size());
    std::printf("%-12s %9.0f tris  %u thr  wall %6.3f s (min %.3f, max %.3f)  %5.2f Mtris/s  cpu %6.3f s  SAH %7.2f  "
                "nodes %8u  depth %2u  leaf avg %.2f  %6.1f MB  peak RSS %.0f MB\n",
                label, triangles, threads, median, seconds.front(), seconds.back(), triangles / median * 1e-6,
                cpuSeconds[cpuSeconds.size() / 2],
                bvh.stats.sahCost, bvh.stats.nodeCount, bvh.stats.maxDepth, bvh.stats.averageLeafTriangles,
                double(bvh.stats.bytes) / (1 << 20), peakRssMegabytes());
    std::fflush(stdout);
}

void benchTrace(const Scene& scene, const char* label, uint32_t rayCount) {
    const Bvh bvh = buildBvh(scene);
    std::mt19937 rng(1);
    std::vector<Ray> rays;
    const Aabb bounds = scene.bounds();
    for (uint32_t i = 0; i < rayCount; ++i) {
        rays.push_back(test::makeRandomRay(rng, bounds, 0.2f));
    }
    // Validate a sample against brute force before printing a speed (tinybvh practice).
    int mismatches = 0;
    for (uint32_t i = 0; i < 50; ++i) {
        const Hit expected = test::traceBruteForce(scene, rays[i]);
        const Hit actual = traceClosestCpu(bvh, rays[i]);
        mismatches += (expected.triangleId != actual.triangleId || expected.t != actual.t) ? 1 : 0;
    }
    std::vector<Hit> hits(rays.size());
    for (bool anyHit : {false, true}) {
        traceCpu(bvh, rays, hits, anyHit); // warm-up
        const auto start = std::chrono::steady_clock::now();
        traceCpu(bvh, rays, hits, anyHit);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const auto hitCount = std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.hit(); });
        std::printf("%-22s %s: %u rays  %.3f s  %.2f MRays/s  %.0f%% hit  (%d/50 brute-force mismatches)\n", label,
                    anyHit ? "any-hit    " : "closest-hit", rayCount, seconds, rayCount / seconds * 1e-6,
                    100.0 * double(hitCount) / rayCount, mismatches);
    }
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const bool large = argc > 1 && std::strcmp(argv[1], "--large") == 0;
    if (argc > 1 && std::strcmp(argv[1], "--profile") == 0) { // one scene, one thread, for perf record
        benchBuild(test::makeTriangleSoup(1000000, 42), "soup", 1, 3);
        return 0;
    }
    const uint32_t allThreads = std::max(1u, std::thread::hardware_concurrency());
    const int runs = quick ? 1 : 3;
    const std::vector<uint32_t> soupSizes = quick ? std::vector<uint32_t>{100000} : std::vector<uint32_t>{1000000, 5000000};
    for (uint32_t n : soupSizes) {
        // Random small triangles (edge <= 1) in a cube whose side grows with n, so the density stays fixed.
        const Scene soup = test::makeTriangleSoup(n, 42, 100.0f * std::cbrt(float(n) / 1e6f), 1.0f);
        benchBuild(soup, "soup", 1, runs);
        benchBuild(soup, "soup", allThreads, runs);
    }
    for (uint32_t n : soupSizes) {
        const auto cells = uint32_t(std::sqrt(double(n) / 2.0)); // 2 triangles per cell
        const Scene field = test::makeHeightfield(cells, 43);
        benchBuild(field, "heightfield", 1, runs);
        benchBuild(field, "heightfield", allThreads, runs);
    }
    {
        const Scene clusters = test::makeClusteredSoup(quick ? 100000 : 1000000, 50, 44);
        benchBuild(clusters, "clustered", allThreads, runs);
    }
    if (large) {
        const Scene soup = test::makeTriangleSoup(10000000, 45, 100.0f * std::cbrt(10.0f), 1.0f);
        std::printf("10M soup scene generated, peak RSS %.0f MB\n", peakRssMegabytes());
        benchBuild(soup, "soup", allThreads, 1);
    }
    benchTrace(test::makeTriangleSoup(quick ? 100000 : 1000000, 46), "trace soup", quick ? 100000 : 1000000);
    benchTrace(test::makeHeightfield(quick ? 200 : 700, 47), "trace heightfield", quick ? 100000 : 1000000);
    return 0;
}
