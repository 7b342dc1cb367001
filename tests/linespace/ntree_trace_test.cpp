// N-tree shadow tracing (method ntree+ls; shaders/linespace/ntree_traverse.glsl through NTreeTracer) against
// pure BVH tracing on procedural scenes:
//  - with no terminating level (shadowLevel >= d) the N-tree traversal is exact: the same occlusion answer as
//    the BVH for every shadow ray (DDA, leaf triangle lists, exact empty-shaft skipping);
//  - at the paper's level d - 1 with the start node traversed exactly, an occupied shaft only adds occlusion
//    (SS §4: "a rather conservative estimation of occlusion"): every ray occluded for the BVH stays occluded,
//    and some rays really end at a shaft;
//  - skipping the start node (SS §4.1) can only lose occlusion against traversing it exactly;
//  - treating nodes near the origin like the start node (exactly) lies between the exact and the paper's answer;
//  - the GPU pools describe the tree: every cell's entry names its subdivided node, its leaf (with the cell's
//    triangle list) or is empty.
#include "tests/render/render_fixture.h"

#include "linespace/ntree.h"
#include "linespace/ntree_gpu.h"
#include "linespace/ntree_tracer.h"
#include "renderer/core/error.h"
#include "renderer/scene/camera_path.h"
#include "shaders/shared/linespace_bindings.h"
#include "shaders/shared/ntree_layout.h"

namespace chcrt::test {
namespace {

struct NTreeCase {
    const char* scene;
    uint32_t n;
    uint32_t depth;
};

class NTreeTraceTest : public RenderTest, public ::testing::WithParamInterface<NTreeCase> {
protected:
    std::shared_ptr<ls::NTreeGpu> buildGpu(const NTreeCase& c) {
        ls::NTreeParams params;
        params.n = c.n;
        params.depth = c.depth;
        tree_ = ls::buildNTree(bvh_, params);
        return std::make_shared<ls::NTreeGpu>(tree_);
    }
    // Shadow-ray hits of pure BVH tracing and of each tracer, for the rays of (frame, sample).
    struct Pass {
        std::vector<Ray> rays;
        std::vector<Hit> reference;
        std::vector<std::vector<Hit>> hits;
    };
    Pass tracePass(Renderer& renderer, const std::vector<Tracer*>& tracers, int frame, int sample) {
        const Camera camera = proceduralNearPath(spec_).cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        renderer.generateRayPass(camera, RayType::Shadow, sample, stats);
        Pass pass;
        renderer.useTracer(nullptr);
        renderer.traceRayPass(camera, RayType::Shadow, sample, stats);
        pass.reference = renderer.readHits(0);
        for (Tracer* tracer : tracers) {
            renderer.useTracer(tracer);
            renderer.traceRayPass(camera, RayType::Shadow, sample, stats);
            pass.hits.push_back(renderer.readHits(0));
        }
        renderer.useTracer(nullptr);
        pass.rays = renderer.readRays(0);
        cappedRays_ += stats.cappedRays;
        return pass;
    }
    ls::NTree tree_;
    uint64_t cappedRays_ = 0;
};

bool occluded(const Hit& hit) { return hit.triangleId != CHCRT_NO_HIT_ID; }

TEST_P(NTreeTraceTest, WithoutTerminationItIsExact) {
    const NTreeCase c = GetParam();
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    ls::NTreeShadowOptions exact;
    exact.shadowLevel = c.depth; // no level terminates
    ls::NTreeTracer tracer("ntree+ls", buildGpu(c), exact);
    uint64_t compared = 0, occludedRays = 0;
    for (int frame : {0, 3}) {
        for (int sample = 0; sample < 2; ++sample) {
            const Pass pass = tracePass(renderer, {&tracer}, frame, sample);
            for (size_t i = 0; i < pass.rays.size(); ++i) {
                if (!(pass.rays[i].tmax > pass.rays[i].tmin)) continue;
                ++compared;
                occludedRays += occluded(pass.reference[i]);
                ASSERT_EQ(occluded(pass.hits[0][i]), occluded(pass.reference[i]))
                    << "frame " << frame << " sample " << sample << " pixel " << i;
                ASSERT_NE(pass.hits[0][i].triangleId, CHCRT_LS_OCCLUDED_ID) << "terminated without a level";
            }
        }
    }
    EXPECT_EQ(cappedRays_, 0u);
    EXPECT_GT(compared, 10000u);
    EXPECT_GT(occludedRays, 10u);
}

TEST_P(NTreeTraceTest, ShaftTerminationOnlyAddsOcclusion) {
    const NTreeCase c = GetParam();
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    auto gpu = buildGpu(c);
    ls::NTreeShadowOptions paperLevel;
    paperLevel.shadowLevel = c.depth - 1;
    paperLevel.startExact = true;
    ls::NTreeShadowOptions skipStart = paperLevel;
    skipStart.startExact = false;
    ls::NTreeShadowOptions nearExact = paperLevel;
    nearExact.nearEdges = 1.0f;
    ls::NTreeTracer exactStart("ntree+ls", gpu, paperLevel);
    ls::NTreeTracer paper("ntree+ls", gpu, skipStart);
    ls::NTreeTracer near("ntree+ls", gpu, nearExact);
    uint64_t terminated = 0, occludedPure = 0, occludedNTree = 0;
    for (int frame : {0, 3}) {
        const Pass pass = tracePass(renderer, {&exactStart, &paper, &near}, frame, 0);
        for (size_t i = 0; i < pass.rays.size(); ++i) {
            if (!(pass.rays[i].tmax > pass.rays[i].tmin)) continue;
            const bool pure = occluded(pass.reference[i]);
            const bool withStart = occluded(pass.hits[0][i]);
            const bool skipping = occluded(pass.hits[1][i]);
            ASSERT_TRUE(!pure || withStart) << "shaft termination lost an occluder at pixel " << i;
            ASSERT_TRUE(!skipping || withStart) << "skipping the start node added occlusion at pixel " << i;
            // Near nodes traversed exactly instead of terminating: between the exact answer and the paper's.
            const bool nearOccluded = occluded(pass.hits[2][i]);
            ASSERT_TRUE(!pure || nearOccluded) << "near-exact traversal lost an occluder at pixel " << i;
            ASSERT_TRUE(!nearOccluded || withStart) << "near-exact traversal added occlusion at pixel " << i;
            occludedPure += pure;
            occludedNTree += withStart;
            terminated += pass.hits[0][i].triangleId == CHCRT_LS_OCCLUDED_ID;
        }
    }
    EXPECT_EQ(cappedRays_, 0u);
    EXPECT_GT(occludedPure, 0u);
    EXPECT_GE(occludedNTree, occludedPure);
    EXPECT_GT(terminated, 0u) << "no shaft terminated a ray: the approximation was not exercised";
}

std::string caseName(const ::testing::TestParamInfo<NTreeCase>& info) {
    std::string name = std::string(info.param.scene) + "_N" + std::to_string(info.param.n) + "_d" +
                       std::to_string(info.param.depth);
    for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(ProceduralScenes, NTreeTraceTest,
                         ::testing::Values(NTreeCase{"city:30k", 4, 3}, NTreeCase{"city:30k", 6, 2},
                                           NTreeCase{"interior:5k", 4, 2}, NTreeCase{"plant:10k", 4, 3},
                                           NTreeCase{"plane-and-box", 8, 2}),
                         caseName);

// The pools the shader reads are the tree: walk every subdivided node's cells through the pools and compare.
TEST(NTreePools, DescribeTheTree) {
    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec("plant:5k", spec));
    const Scene scene = generateProceduralScene(spec);
    const Bvh bvh = buildBvh(scene);
    ls::NTreeParams params;
    params.n = 4;
    params.depth = 3;
    const ls::NTree tree = ls::buildNTree(bvh, params);
    const ls::NTreePools pools = ls::makeNTreePools(tree);
    const uint32_t cells = params.n * params.n * params.n;
    ASSERT_EQ(pools.nodes.size(), 4u * tree.stats.subdividedCount);
    ASSERT_EQ(pools.tree.size(), size_t(cells) * tree.stats.subdividedCount);
    uint64_t leaves = 0;
    for (const ls::NTreeNode& node : tree.nodes) {
        if (node.space == ls::kNoChild) continue;
        EXPECT_EQ(pools.nodes[4 * node.space + 3], node.size);
        EXPECT_EQ(pools.nodes[4 * node.space + 0], node.lower.x);
        for (uint32_t c = 0; c < cells; ++c) {
            const ls::NTreeNode& child = tree.nodes[node.firstChild + c];
            const uint32_t entry = pools.tree[size_t(node.space) * cells + c];
            if (child.space != ls::kNoChild) {
                EXPECT_EQ(entry, child.space);
            } else if (child.triangleCount == 0) {
                EXPECT_EQ(entry, CHCRT_NT_EMPTY);
            } else {
                ASSERT_NE(entry & CHCRT_NT_LEAF_BIT, 0u);
                const uint32_t leaf = entry & ~CHCRT_NT_LEAF_BIT;
                ASSERT_EQ(pools.leaves[2 * leaf + 1], child.triangleCount);
                for (uint32_t r = 0; r < child.triangleCount; ++r) {
                    EXPECT_EQ(pools.triangleRefs[pools.leaves[2 * leaf] + r], tree.triangleRefs[child.firstTriangle + r]);
                }
                ++leaves;
            }
        }
    }
    EXPECT_EQ(leaves, pools.leaves.size() / 2);
    EXPECT_GT(leaves, 0u);
}

TEST(NTreeParams, ParsesNAndDepth) {
    const ls::NTreeParams p = ls::parseNTreeParams("6:3");
    EXPECT_EQ(p.n, 6u);
    EXPECT_EQ(p.depth, 3u);
    for (const char* bad : {"", "6", "6:", ":3", "1:3", "6:0", "6:9", "17:2", "6:3x", "a:b", "6:-1"}) {
        EXPECT_THROW(ls::parseNTreeParams(bad), InputError) << bad;
    }
}

} // namespace
} // namespace chcrt::test
