#ifndef CHCRT_NTREE_LAYOUT_H
#define CHCRT_NTREE_LAYOUT_H
// GPU pools of the N-tree with binary Line Spaces (soft-shadow paper §3.1, Figure 3), shared by the C++ upload
// (linespace/ntree_gpu.cpp) and the traversal (shaders/linespace/ntree_traverse.glsl):
//  - node pool (RGBA32F, one texel per subdivided node): lower corner xyz, cube edge w. The n-th node owns the
//    n-th Line Space (binary words n * CHCRT_LS_BINARY_WORDS_PER_SPACE ...) and the n-th children group of the
//    tree pool (entries n * N^3 ... + N^3 - 1, x fastest, then y, then z), so one index addresses all three.
//  - tree pool (R32UI, one entry per child cell): CHCRT_NT_EMPTY, a subdivided child's node index, or
//    CHCRT_NT_LEAF_BIT | leaf index for a non-empty cell of the deepest level. The paper stores no leaves; we keep
//    them (SS §3.1: "negative values with a special meaning ... references to geometry") so that the node a
//    shadow ray starts in can be traversed exactly, and for the exact reference mode (tests).
//  - leaf pool (RG32UI, per leaf): first triangle reference, reference count;
//  - reference pool (R32UI): indices into the BVH-ordered triangle buffer (bvhTriangles).

#ifndef CHCRT_UNIT_NT_NODES
#define CHCRT_UNIT_NT_NODES 22        // samplerBuffer RGBA32F: lower.xyz, size
#define CHCRT_UNIT_NT_TREE 23         // usamplerBuffer R32UI: children groups
#define CHCRT_UNIT_NT_BINARY_WORDS 24 // usamplerBuffer R32UI: symmetric bitsets, one Line Space per node
#define CHCRT_UNIT_NT_LEAVES 25       // usamplerBuffer RG32UI: (first reference, count) per leaf
#define CHCRT_UNIT_NT_TRIANGLE_REFS 26 // usamplerBuffer R32UI: BVH-order triangle index per reference
#endif

#define CHCRT_NT_EMPTY 0xFFFFFFFFu
#define CHCRT_NT_LEAF_BIT 0x80000000u
// Levels of subdivided nodes a traversal can stack (d <= this); the papers use d = 3 or 4.
#define CHCRT_NT_MAX_DEPTH 8

#endif
