#ifndef CHCRT_LINESPACE_BINDINGS_H
#define CHCRT_LINESPACE_BINDINGS_H
// Texture units and modes of Line Space traversal (shaders/linespace/linespace_traverse.glsl), shared by the
// C++ object that uploads and binds the pools (linespace/linespace_gpu.h) and the shaders. Units follow the
// renderer's 0..15 (shared/render_layout.h); a shader that needs other units may define them before including.

#ifndef CHCRT_UNIT_LS_SPACE_OF_NODE
#define CHCRT_UNIT_LS_SPACE_OF_NODE 16   // usamplerBuffer R32UI, per BVH node: its Line Space or CHCRT_LS_NO_SPACE
#define CHCRT_UNIT_LS_BINARY_WORDS 17    // usamplerBuffer R32UI: symmetric bitsets, words-per-space each
#define CHCRT_UNIT_LS_CANDIDATE_WORDS 18 // usamplerBuffer R32UI: non-symmetric bitsets (Algorithm 2)
#define CHCRT_UNIT_LS_CANDIDATE_OFFSETS 19 // usamplerBuffer R32UI: prefix sum per word (absolute data slot)
#define CHCRT_UNIT_LS_CANDIDATE_DATA 20  // usamplerBuffer R32UI: candidate = index into the BVH triangle buffer
#define CHCRT_UNIT_LS_VERTEX_NORMALS 21  // usamplerBuffer RGBA32UI, per BVH-order triangle: octahedral 16:16
                                         // vertex normals n0, n1, n2 and the mean normal (RC §3.1 rejection)
#endif

#define CHCRT_LS_NO_SPACE 0xFFFFFFFFu
// Triangle id reported by a shadow ray that an occupied shaft terminated (SS §4.1): not a real triangle, only
// "occluded"; shading reads nothing else from a shadow hit.
#define CHCRT_LS_OCCLUDED_ID 0xFFFFFFFEu

// CHCRT_LS_MODE: what a traversal does at a Line Space node (a BVH node of the cut chosen by D and T).
#define CHCRT_LS_MODE_OFF 0        // pure BVH (default: every shader that does not ask stays unchanged)
#define CHCRT_LS_MODE_EXACT 1      // binary bit 0 -> skip the node (exact empty-space skipping)
#define CHCRT_LS_MODE_SHADOW 2     // bit 1 -> occluded (SS §4.1), bit 0 -> skip; the start node is traversed
#define CHCRT_LS_MODE_CANDIDATE 3  // the shaft's candidate as a plane (RC Algorithm 1); nodes act as leaves

#endif
