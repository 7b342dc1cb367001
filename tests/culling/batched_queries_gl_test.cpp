// BatchedQueries (shaders/culling/chcrt_query_batch.comp.glsl) against the §4.1 rule evaluated on the CPU with the
// same shared functions traversal prunes with: per pair, the tile's active rays that meet one of its boxes with entry
// <= pruneLimit(nearest t so far). Random rays with and without hits over tiles larger than a work item, offset and
// one-pixel tiles, two boxes per pair, rays starting inside a box, boxes touching the hit distance (and one float
// beyond it), NaN and infinite values, inactive rays, any-hit rays that finished, and the visible threshold.
#include "culling/batched_queries.h"
#include "renderer/gl/context.h"
#include "renderer/render/trace_pass.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/intersect.h"
#include "shaders/shared/render_layout.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>

namespace chcrt {
namespace {

using gpu::intersectRayAabb;
using gpu::pruneLimit;
using gpu::rayHitsAabb;
using gpu::safeInverseDirection;

constexpr int kW = 83, kH = 61; // 5,063 pixels: a whole-screen tile takes 5 work items

struct RaySet {
    std::vector<glm::vec4> origins = std::vector<glm::vec4>(size_t(kW) * kH);
    std::vector<glm::vec4> directions = std::vector<glm::vec4>(size_t(kW) * kH);
    std::vector<glm::uvec4> hits = std::vector<glm::uvec4>(size_t(kW) * kH);
    GlTexture origin, direction, hit;

    RaySet() {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f), t(0.0f, 1.0f), coin(0.0f, 1.0f);
        const auto miss = missHitTexel();
        for (size_t i = 0; i < origins.size(); ++i) {
            const float tmin = 0.01f * t(rng);
            origins[i] = glm::vec4(8.0f * u(rng), 8.0f * u(rng), 8.0f * u(rng), tmin);
            directions[i] = glm::vec4(glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.001f)),
                                      tmin + 30.0f * t(rng));
            hits[i] = coin(rng) < 0.5f ? glm::uvec4(miss[0], miss[1], miss[2], miss[3])
                                       : glm::uvec4(std::bit_cast<uint32_t>(tmin + 10.0f * t(rng)), 5u, 0u, 0u);
            if (coin(rng) < 0.05f) directions[i].w = origins[i].w; // inactive
        }
        // Row 0: rays along +x from the origin's yz plane, hitting at t = 2, against the touching boxes below.
        for (int x = 0; x < 8; ++x) {
            origins[size_t(x)] = glm::vec4(0.0f, float(x), 0.0f, 0.0f);
            directions[size_t(x)] = glm::vec4(1.0f, 0.0f, 0.0f, 100.0f);
            hits[size_t(x)] = glm::uvec4(std::bit_cast<uint32_t>(2.0f), 9u, 0u, 0u);
        }
        // Row 1: a NaN origin, a NaN direction, an infinite tmax, a NaN tmax.
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        origins[size_t(kW) + 0].x = nan;
        directions[size_t(kW) + 1].y = nan;
        directions[size_t(kW) + 2].w = inf;
        hits[size_t(kW) + 2] = glm::uvec4(miss[0], miss[1], miss[2], miss[3]);
        directions[size_t(kW) + 3].w = nan;
        origin = createTexture2D(kW, kH, GL_RGBA32F);
        direction = createTexture2D(kW, kH, GL_RGBA32F);
        hit = createTexture2D(kW, kH, GL_RGBA32UI);
        glTextureSubImage2D(origin.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, origins.data());
        glTextureSubImage2D(direction.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, directions.data());
        glTextureSubImage2D(hit.id(), 0, 0, 0, kW, kH, GL_RGBA_INTEGER, GL_UNSIGNED_INT, hits.data());
        glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, origin.id());
        glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, direction.id());
        glBindImageTexture(CHCRT_CULLING_IMAGE_HIT, hit.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
    }

    // The §4.1 rule on the CPU: how many active rays of the query's tile reach one of its boxes.
    uint32_t expectedCount(const BatchedQueries::Query& q, bool anyHit) const {
        uint32_t count = 0;
        for (int y = q.tile.y; y < q.tile.y + q.tile.height; ++y) {
            for (int x = q.tile.x; x < q.tile.x + q.tile.width; ++x) {
                const size_t i = size_t(y) * kW + size_t(x);
                const glm::vec4 o = origins[i], d = directions[i];
                if (!(d.w > o.w)) continue;
                const bool hasHit = hits[i].y != CHCRT_NO_HIT_ID;
                if (anyHit && hasHit) continue;
                const float limit = pruneLimit(hasHit ? std::bit_cast<float>(hits[i].x) : d.w);
                const glm::vec3 invDir = safeInverseDirection(glm::vec3(d));
                bool reaches = false;
                for (uint32_t b = 0; b < q.boxCount; ++b) {
                    reaches = reaches ||
                              rayHitsAabb(intersectRayAabb(glm::vec3(o), invDir, q.boxMin[b], q.boxMax[b]), o.w, limit);
                }
                count += reaches ? 1u : 0u;
            }
        }
        return count;
    }
};

BatchedQueries::Query query(Tile tile, glm::vec3 lo, glm::vec3 hi) {
    BatchedQueries::Query q;
    q.tile = tile;
    q.boxMin[0] = lo;
    q.boxMax[0] = hi;
    return q;
}

TEST(BatchedQueriesGl, CountsEqualTheQueryRuleOnTheCpu) {
    auto context = createHeadlessContext(GlBackend::Egl, true);
    RaySet rays;
    std::vector<BatchedQueries::Query> queries;
    const Tile screen{0, 2, kW, kH - 2}; // all but rows 0 and 1 (the special rays below)
    queries.push_back(query(screen, glm::vec3(-2.0f), glm::vec3(2.0f)));            // rays start inside it
    queries.push_back(query(screen, glm::vec3(20.0f), glm::vec3(21.0f)));           // far: few rays reach it
    queries.push_back(query(Tile{17, 9, 40, 33}, glm::vec3(-9.0f, 3.0f, -1.0f), glm::vec3(-4.0f, 6.0f, 9.0f)));
    queries.push_back(query(Tile{70, 50, 1, 1}, glm::vec3(-30.0f), glm::vec3(30.0f))); // one pixel
    BatchedQueries::Query two = query(Tile{5, 20, 64, 40}, glm::vec3(3.0f, -8.0f, -8.0f), glm::vec3(4.0f, 8.0f, 8.0f));
    two.boxCount = 2;
    two.boxMin[1] = glm::vec3(-12.0f, -1.0f, 5.0f);
    two.boxMax[1] = glm::vec3(-6.0f, 1.0f, 12.0f);
    queries.push_back(two);
    // Row 0's rays hit at t = 2: a box entered exactly at pruneLimit(2) is reached (traversal would enter it), one
    // entered a float later is not; the rays of row 1 against a box around everything: an infinite tmax reaches it,
    // a NaN tmax is inactive, and NaN origins or directions give whatever GLSL's min and max make of a NaN (undefined;
    // traversal runs the same intersectRayAabb, so the query and traversal agree), at most their one ray each.
    const float limit = pruneLimit(2.0f);
    const float beyond = std::nextafter(limit, 100.0f);
    queries.push_back(query(Tile{0, 0, 8, 1}, glm::vec3(limit, -1.0f, -1.0f), glm::vec3(limit + 1.0f, 8.0f, 1.0f)));
    queries.push_back(query(Tile{0, 0, 8, 1}, glm::vec3(beyond, -1.0f, -1.0f), glm::vec3(beyond + 1.0f, 8.0f, 1.0f)));
    queries.push_back(query(Tile{2, 1, 1, 1}, glm::vec3(-1e6f), glm::vec3(1e6f)));
    queries.push_back(query(Tile{3, 1, 1, 1}, glm::vec3(-1e6f), glm::vec3(1e6f)));
    queries.push_back(query(Tile{0, 1, 2, 1}, glm::vec3(-1e6f), glm::vec3(1e6f)));

    BatchedQueries batched;
    for (bool anyHit : {false, true}) {
        SCOPED_TRACE(anyHit ? "any hit" : "closest hit");
        std::vector<uint32_t> counts;
        batched.test(queries, anyHit, std::numeric_limits<uint32_t>::max() - 1, false, counts);
        ASSERT_EQ(counts.size(), queries.size());
        for (size_t i = 0; i + 1 < queries.size(); ++i) {
            EXPECT_EQ(counts[i], rays.expectedCount(queries[i], anyHit)) << "query " << i;
        }
        EXPECT_GT(counts[0], 100u);
        EXPECT_GT(counts[4], 0u);
        EXPECT_EQ(counts[5], anyHit ? 0u : 8u); // any-hit rays that hit are finished
        EXPECT_EQ(counts[6], 0u);
        EXPECT_EQ(counts[7], 1u); // infinite tmax
        EXPECT_EQ(counts[8], 0u); // NaN tmax
        EXPECT_LE(counts[9], 2u); // NaN origin, NaN direction
    }
    // A threshold stops counting once a pair is decided: above it, and never more than all the rays that reach it.
    std::vector<uint32_t> counts;
    batched.test(queries, false, 3u, false, counts);
    EXPECT_GT(counts[0], 3u);
    EXPECT_LE(counts[0], rays.expectedCount(queries[0], false));
    EXPECT_EQ(counts[6], 0u);
    // An empty round reads nothing back.
    batched.test({}, false, 0u, false, counts);
    EXPECT_TRUE(counts.empty());
}

} // namespace
} // namespace chcrt
