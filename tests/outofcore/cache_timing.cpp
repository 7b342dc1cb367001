// GPU subtree cache timing (not a test; prints per-frame Table 3 style counters). A point moves across the
// prepared scene at street level; each "frame" requests, nearest first and in batches of 16, the subtrees whose
// boxes lie within a radius of it (a stand-in for CHC+RT's visible set until the tracer uses the cache).
//   build/bin/outofcore_cache_timing file.chs [gpu-cache-mb=1024] [policy=lru] [frames=60] [radius=150] [host-mb=2048]
#include "culling/outofcore/gpu_subtree_cache.h"
#include "renderer/gl/context.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace chcrt;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s file.chs [gpu-cache-mb] [lru|round-robin] [frames] [radius] [host-mb]\n", argv[0]);
        return 2;
    }
    try {
        const uint64_t gpuMb = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1024;
        const outofcore::CachePolicy policy = outofcore::parseCachePolicy(argc > 3 ? argv[3] : "lru");
        const int frames = argc > 4 ? std::atoi(argv[4]) : 60;
        const float radius = argc > 5 ? float(std::atof(argv[5])) : 150.0f;
        const uint64_t hostMb = argc > 6 ? std::strtoull(argv[6], nullptr, 10) : 2048;
        const auto context = createHeadlessContext(GlBackend::Egl, false);
        const outofcore::ChsFile file(argv[1]);
        outofcore::SubtreeStore store(file, hostMb << 20);
        outofcore::GpuSubtreeCache cache(store, {gpuMb << 20, policy});
        const outofcore::ChsHeader& h = file.header();
        std::printf("%s: %u subtrees, cache %u slots, allocated %.1f MB of %llu MB, policy %s\n", argv[1],
                    h.subtreeCount, cache.slotCount(), double(cache.stats().allocatedBytes) / 1048576.0,
                    (unsigned long long)gpuMb, outofcore::toString(policy));
        const glm::vec3 lo(h.boundsMin[0], h.boundsMin[1], h.boundsMin[2]), hi(h.boundsMax[0], h.boundsMax[1], h.boundsMax[2]);
        double totalMs = 0;
        outofcore::GpuCacheStats sum;
        uint64_t requested = 0;
        for (int f = 0; f < frames; ++f) {
            const float s = frames > 1 ? float(f) / float(frames - 1) : 0.5f;
            const glm::vec3 p(lo.x + (0.3f + 0.4f * s) * (hi.x - lo.x), 1.7f, 0.5f * (lo.z + hi.z));
            std::vector<std::pair<float, uint32_t>> near;
            for (uint32_t i = 0; i < h.subtreeCount; ++i) {
                const auto& r = file.subtrees()[i];
                glm::vec3 q;
                for (int k = 0; k < 3; ++k) q[k] = std::clamp(p[k], r.boundsMin[k], r.boundsMax[k]);
                const float d = glm::length(q - p);
                if (d <= radius) near.emplace_back(d, i);
            }
            std::sort(near.begin(), near.end());
            cache.resetCounters();
            const auto start = std::chrono::steady_clock::now();
            for (size_t b = 0; b < near.size(); b += 16) {
                std::vector<uint32_t> batch, roots;
                for (size_t k = b; k < std::min(near.size(), b + 16); ++k) batch.push_back(near[k].second);
                roots.resize(batch.size());
                cache.acquire(batch, roots);
            }
            glFinish();
            const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            totalMs += ms;
            requested += near.size();
            const auto& st = cache.stats();
            sum.hits += st.hits, sum.misses += st.misses, sum.evictions += st.evictions;
            sum.uploadedNodeBytes += st.uploadedNodeBytes, sum.uploadedTriangleBytes += st.uploadedTriangleBytes;
            if (st.allocatedBytes > (gpuMb << 20)) { std::fprintf(stderr, "budget exceeded\n"); return 1; }
        }
        const auto host = store.stats();
        std::printf("per frame: %.1f subtrees requested, %.1f hits, %.1f misses, %.1f evictions, "
                    "%.1f MB BVH + %.1f MB geometry uploaded, %.1f ms\n",
                    double(requested) / frames, double(sum.hits) / frames, double(sum.misses) / frames,
                    double(sum.evictions) / frames, double(sum.uploadedNodeBytes) / 1048576.0 / frames,
                    double(sum.uploadedTriangleBytes) / 1048576.0 / frames, totalMs / frames);
        std::printf("resident %.1f MB in %u subtrees; host store: %llu reads, %.1f MB read, peak %.1f MB of %llu MB\n",
                    double(cache.stats().residentBytes) / 1048576.0, cache.stats().residentSubtrees,
                    (unsigned long long)host.misses, double(host.bytesRead) / 1048576.0,
                    double(host.peakResidentBytes) / 1048576.0, (unsigned long long)hostMb);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
}
