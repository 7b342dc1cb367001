// Prefetch along a walkthrough (out of core, subtree_prefetch.h): reading ahead into the host store changes no
// hit (the store's contents equal the file's whatever is read when), the look-ahead's subtrees are used by later
// frames (prefetch hits), and the host store and the GPU cache stay within their budgets (their peaks, from the
// counters) with a host budget that holds a fraction of the scene.
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/render/hit_comparison.h"
#include "shaders/shared/bvh_layout.h"
#include "tests/outofcore/outofcore_test_util.h"
#include "tests/render/render_fixture.h"

#include <gtest/gtest.h>

#include <cstring>

namespace chcrt {
namespace {

using PrefetchWalkthroughTest = test::RenderTest;

TEST_F(PrefetchWalkthroughTest, ChangesNoHitHitsOnTheLookAheadAndKeepsTheBudgets) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:200k", file, 1000);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    Renderer renderer(loaded.scene, loaded.bvh, loaded.light, settings);

    outofcore::OutOfCoreOptions options;
    uint64_t fileBytes = 0, gpuBytes = 0;
    {
        const outofcore::ChsFile chs(file);
        for (const outofcore::ChsSubtreeRecord& r : chs.subtrees()) {
            fileBytes += r.bytes;
            gpuBytes += uint64_t(r.nodeCount) * sizeof(BvhNodeGpu) + uint64_t(r.triangleCount) * sizeof(TriangleGpu);
        }
    }
    options.hostCacheBytes = fileBytes / 3; // a third of the scene: the store evicts along the walk
    options.gpuCacheBytes = gpuBytes / 3; // uploads along the walk, not a thrashing cache (whose host reads no
                                          // read-ahead can serve: a frame would evict what it read ahead)
    ChcrtOptions chcrt;
    chcrt.pairs.minTileSize = 16;
    options.prefetchFrames = 0;
    outofcore::OutOfCoreTracer plain(file, options, chcrt);
    options.prefetchFrames = 2;
    outofcore::OutOfCoreTracer prefetching(file, options, chcrt);

    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec(loaded.source, spec));
    const CameraPath path = proceduralNearPath(spec);
    std::vector<Camera> cameras;
    // Frames far enough apart to need new subtrees.
    for (int frame = 0; frame < 8; ++frame) cameras.push_back(path.cameraAtFrame(frame * 30));
    uint64_t compared = 0;
    for (size_t f = 0; f < cameras.size(); ++f) {
        const Camera& camera = cameras[f];
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
            renderer.generateRayPass(camera, type, 0, stats);
            renderer.useTracer(&plain);
            renderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> without = renderer.readHits(0);
            renderer.useTracer(&prefetching);
            renderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> with = renderer.readHits(0);
            renderer.useTracer(nullptr);
            ASSERT_EQ(with.size(), without.size());
            EXPECT_EQ(0, std::memcmp(with.data(), without.data(), with.size() * sizeof(Hit)))
                << toString(type) << " frame " << f;
            compared += with.size();
        }
        const std::span<const Camera> next(cameras.data() + f + 1, cameras.size() - f - 1);
        plain.prefetchAfterFrame(camera, next, settings.width, settings.height);
        prefetching.prefetchAfterFrame(camera, next, settings.width, settings.height);
        prefetching.store().waitForPrefetch(); // the counters below then do not depend on the thread's timing
    }
    EXPECT_GT(compared, 0u);
    const outofcore::OutOfCoreStats p = plain.snapshot(), q = prefetching.snapshot();
    EXPECT_EQ(p.prefetchReads, 0u) << "--prefetch-frames 0 reads nothing ahead";
    EXPECT_GT(q.prefetchReads, 0u);
    EXPECT_GT(q.prefetchHits, 0u) << "the look-ahead predicted subtrees that later frames used";
    EXPECT_LE(q.prefetchHits, q.prefetchReads);
    for (const outofcore::OutOfCoreStats& s : {p, q}) {
        EXPECT_GT(s.hostPeakResidentBytes, 0u);
        EXPECT_LE(s.hostPeakResidentBytes, options.hostCacheBytes);
        EXPECT_GT(s.peakResidentBytes, 0u);
        EXPECT_LE(s.peakResidentBytes, options.gpuCacheBytes);
    }
    // Reads the frames themselves had to wait for: fewer when some came from the prefetch.
    std::printf("demand reads without prefetch %llu, with %llu (+%llu prefetched, %llu hits, %llu B wasted)\n",
                (unsigned long long)p.hostReads, (unsigned long long)(q.hostReads - q.prefetchReads),
                (unsigned long long)q.prefetchReads, (unsigned long long)q.prefetchHits,
                (unsigned long long)q.prefetchWastedBytes);
}

} // namespace
} // namespace chcrt
