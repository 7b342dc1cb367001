#pragma once
// CHC+RT batched queries (`--chcrt-queries batched`; culling/README.md "Deciding pairs"): the pairs that need a
// ray-exact test in a round of Algorithm 1 are tested by one compute dispatch, each counting into a slot of a
// buffer that is read back once per round — instead of one GL occlusion query object, one draw and one blocking
// read per pair (about 13 µs + 7 ns per tile pixel each on llvmpipe). The test is the §4.1 generalized query:
// a tile's ray reaches a pair when it meets one of the pair's boxes before its nearest hit so far
// (shaders/culling/chcrt_query_batch.comp.glsl), so pairs decided here are decided exactly as a GL query decides
// them, and hits stay bit-identical to pure BVH tracing.
#include "culling/query_pair_hierarchy.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace chcrt {

class BatchedQueries {
public:
    // One query of a round: the pair's tile and its boxes (the node's box, or its children's with §5.1 tighter
    // bounds).
    struct Query {
        Tile tile;
        uint32_t boxCount = 1; // 1 or 2
        glm::vec3 boxMin[2]{}, boxMax[2]{};
    };

    // Compiles the test's programs now, so that no trace pays for it.
    BatchedQueries();

    // Tests every query of `queries` against the ray textures and the hit image bound as the subtree passes bind
    // them (culling_layout.h), after the image stores of earlier passes; `counts` gets per query how many of its
    // tile's rays reach its boxes, counted until the count exceeds `visibleThreshold` (a larger count decides
    // nothing more). `debugOverdraw`: add each tested ray to the debug image (bound at CHCRT_CULLING_IMAGE_DEBUG).
    void test(const std::vector<Query>& queries, bool anyHit, uint32_t visibleThreshold, bool debugOverdraw,
              std::vector<uint32_t>& counts);

private:
    const ShaderProgram& program(bool anyHit, bool debugOverdraw);

    ShaderProgram programs_[2][2]; // [anyHit][debugOverdraw]; the debug variants compiled on first use
    GlBuffer input_, counts_;
    size_t inputCapacity_ = 0, countCapacity_ = 0; // uvec4s, uints
    std::vector<glm::uvec4> staging_;
};

} // namespace chcrt
