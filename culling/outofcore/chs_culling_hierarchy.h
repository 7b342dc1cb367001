#pragma once
// The CHC+RT culling hierarchy (culling/culling_hierarchy.h) of a prepared scene, read from its file: the
// upper nodes and the subtree directory, plus two node reads per subtree for the §5.1 tighter bounds of the
// termination roots (the boxes of each root's children). Nothing else of the subtrees is read, so building it
// costs O(subtrees) small reads however large the file is (CHC+RT §5.4: only the upper part is resident).
//
// Indices: hierarchy node i = upper node i of the file, subtree i = directory entry i (what GpuSubtreeCache
// expects), Subtree::bvhNode = the upper node index, which is the node index of that subtree's root in the BVH
// of loadPreparedScene (so the in-core BvhSubtreeSource works with this hierarchy too).
#include "culling/culling_hierarchy.h"
#include "renderer/outofcore/chs_file.h"

namespace chcrt::outofcore {

// Throws InputError when the file's upper hierarchy is inconsistent (child or subtree indices out of range).
CullingHierarchy buildCullingHierarchy(const ChsFile& file);

} // namespace chcrt::outofcore
