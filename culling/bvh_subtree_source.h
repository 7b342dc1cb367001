#pragma once
// The in-core SubtreeSource (§5.4 interface, subtree_source.h): every subtree is always resident in the scene's
// BVH buffers, which the renderer binds before tracing, and its GPU root is its BVH node index.
#include "culling/culling_hierarchy.h"
#include "culling/subtree_source.h"

namespace chcrt {

class BvhSubtreeSource final : public SubtreeSource {
public:
    explicit BvhSubtreeSource(const CullingHierarchy& hierarchy) {
        roots_.reserve(hierarchy.subtrees.size());
        for (const CullingHierarchy::Subtree& s : hierarchy.subtrees) roots_.push_back(s.bvhNode);
    }
    void acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) override {
        for (size_t i = 0; i < subtrees.size(); ++i) gpuRoots[i] = roots_[subtrees[i]];
    }

private:
    std::vector<uint32_t> roots_;
};

} // namespace chcrt
