#include "linespace/ntree_gpu.h"

#include "linespace/shaft_index.h"
#include "shaders/shared/ntree_layout.h"

#include <cstdio>
#include <string>

namespace chcrt::ls {
namespace {

// GL refuses a zero-sized buffer: an empty pool uploads zeros (an empty tree: a zero-size root, no bits set).
template <typename T>
TextureBuffer upload(const std::vector<T>& values, GLenum format) {
    static const uint32_t zeros[4] = {0, 0, 0, 0};
    if (values.empty()) return createTextureBuffer(zeros, sizeof(zeros), format);
    return createTextureBuffer(values.data(), values.size() * sizeof(T), format);
}

} // namespace

NTreePools makeNTreePools(const NTree& tree) {
    NTreePools pools;
    const uint32_t cells = tree.params.n * tree.params.n * tree.params.n;
    // Subdivided nodes in the order of their Line Space index (buildNTree numbers them level by level).
    std::vector<uint32_t> nodeOfSpace;
    for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
        if (tree.nodes[i].space != kNoChild) {
            if (tree.nodes[i].space >= nodeOfSpace.size()) nodeOfSpace.resize(tree.nodes[i].space + 1, kNoChild);
            nodeOfSpace[tree.nodes[i].space] = i;
        }
    }
    for (const uint32_t index : nodeOfSpace) {
        const NTreeNode& node = tree.nodes[index];
        pools.nodes.insert(pools.nodes.end(), {node.lower.x, node.lower.y, node.lower.z, node.size});
        for (uint32_t c = 0; c < cells; ++c) {
            const NTreeNode& child = tree.nodes[node.firstChild + c];
            if (child.space != kNoChild) {
                pools.tree.push_back(child.space);
            } else if (child.triangleCount > 0) {
                pools.tree.push_back(CHCRT_NT_LEAF_BIT | static_cast<uint32_t>(pools.leaves.size() / 2));
                pools.leaves.push_back(static_cast<uint32_t>(pools.triangleRefs.size()));
                pools.leaves.push_back(child.triangleCount);
                pools.triangleRefs.insert(pools.triangleRefs.end(), tree.triangleRefs.begin() + child.firstTriangle,
                                          tree.triangleRefs.begin() + child.firstTriangle + child.triangleCount);
            } else {
                pools.tree.push_back(CHCRT_NT_EMPTY);
            }
        }
    }
    return pools;
}

NTreeGpu::NTreeGpu(const NTree& tree) : n_(tree.params.n), depth_(tree.params.depth) {
    const NTreePools pools = makeNTreePools(tree);
    nodes_ = upload(pools.nodes, GL_RGBA32F);
    tree_ = upload(pools.tree, GL_R32UI);
    binaryWords_ = upload(tree.binaryWords, GL_R32UI);
    leaves_ = upload(pools.leaves, GL_RG32UI);
    triangleRefs_ = upload(pools.triangleRefs, GL_R32UI);
    gpuBytes_ = nodes_.bytes + tree_.bytes + binaryWords_.bytes + leaves_.bytes + triangleRefs_.bytes;
}

void NTreeGpu::bind() const {
    glBindTextureUnit(CHCRT_UNIT_NT_NODES, nodes_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_NT_TREE, tree_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_NT_BINARY_WORDS, binaryWords_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_NT_LEAVES, leaves_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_NT_TRIANGLE_REFS, triangleRefs_.texture.id());
}

std::vector<ShaderDefine> NTreeGpu::defines(const NTreeShadowOptions& options) const {
    char nearText[32];
    std::snprintf(nearText, sizeof(nearText), "%.6ff", double(options.nearEdges));
    return {{"CHCRT_BVH_TRAVERSAL", "\"linespace/ntree_traverse.glsl\""}, // the full-screen tracer's traversal
            {"TRACE_ANY_HIT", "1"}, // shadow rays only
            {"CHCRT_NT_N", std::to_string(n_) + "u"},
            {"CHCRT_NT_BINARY_WORDS_PER_SPACE", std::to_string(lsWordCount(n_, true)) + "u"},
            {"CHCRT_NT_SHADOW_LEVEL", std::to_string(options.shadowLevel)},
            {"CHCRT_NT_START_EXACT", options.startExact ? "1" : "0"},
            {"CHCRT_NT_NEAR", nearText}};
}

} // namespace chcrt::ls
