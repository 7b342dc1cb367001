#pragma once
// The N-tree with binary Line Spaces on the GPU (soft-shadow paper §3.1, Figure 3): node, tree, Line Space,
// leaf and triangle-reference pools as texture buffers (layout: shaders/shared/ntree_layout.h), bound to the
// units CHCRT_UNIT_NT_*, and the defines of shaders/linespace/ntree_traverse.glsl.
#include "linespace/ntree.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"

#include <cstdint>
#include <vector>

namespace chcrt::ls {

// How shadow rays use the N-tree. shadowLevel: nodes of this level terminate a ray at an occupied shaft (SS
// Algorithm 1 "deep enough": depth - 1); shadowLevel >= depth = never (exact any-hit tracing). startExact:
// the node a ray starts or ends in is traversed exactly instead of being skipped (SS §4.1 skips it).
struct NTreeShadowOptions {
    uint32_t shadowLevel = 0;
    bool startExact = false;
    // Shadow-level nodes the ray enters within `nearEdges` node edges of its origin are handled like the start
    // node (our addition: self-occlusion by the surface the ray leaves; 0 = the paper).
    float nearEdges = 0.0f;
};

// The GPU pools in CPU memory (exposed for tests and byte counts).
struct NTreePools {
    std::vector<float> nodes;          // 4 per subdivided node: lower.xyz, size (node index = Line Space index)
    std::vector<uint32_t> tree;        // N^3 per subdivided node: CHCRT_NT_EMPTY, node index, or leaf bit | leaf
    std::vector<uint32_t> leaves;      // 2 per leaf: first reference, count
    std::vector<uint32_t> triangleRefs;
};
NTreePools makeNTreePools(const NTree& tree);

class NTreeGpu {
public:
    // Requires a current GL context. Throws GlError when a pool exceeds the texture-buffer limit.
    explicit NTreeGpu(const NTree& tree);
    void bind() const;
    std::vector<ShaderDefine> defines(const NTreeShadowOptions& options) const;
    uint32_t n() const { return n_; }
    uint32_t depth() const { return depth_; }
    uint64_t gpuBytes() const { return gpuBytes_; }

private:
    uint32_t n_ = 0, depth_ = 0;
    TextureBuffer nodes_, tree_, binaryWords_, leaves_, triangleRefs_;
    uint64_t gpuBytes_ = 0;
};

} // namespace chcrt::ls
