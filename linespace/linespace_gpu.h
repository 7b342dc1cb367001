#pragma once
// Line Spaces on the GPU: the pools of linespace_build.h uploaded as texture buffers (~10x faster than SSBOs on
// llvmpipe), bound to the units of shaders/shared/linespace_bindings.h, plus the shader defines a traversal
// compiles with.
// Any shader that includes shaders/render/bvh_traverse.glsl (the pure tracer, CHC+RT subtrees) uses Line Spaces
// by compiling with defines(mode, ...) and calling bind() before drawing.
#include "linespace/linespace_build.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace chcrt::ls {

// CHCRT_LS_MODE_* of shaders/shared/linespace_bindings.h.
// CandidateExactStart: candidates, but the node a ray starts in is traversed exactly (SS §4.1's rule applied
// to candidates: removes most self-occlusion by neighbouring candidate planes, costs speed).
enum class LineSpaceMode { Off = 0, Exact = 1, Shadow = 2, Candidate = 3, CandidateExactStart = 4 };
// Which candidate planes may be hit from behind (CHCRT_LS_CANDIDATE_FRONT_ONLY = the enum's value): Both = the
// paper; FrontInStartNode = only front sides in the node the ray starts in (default of LineSpaceModes);
// Front = only front sides anywhere.
enum class CandidateFaces { Both = 0, FrontInStartNode = 1, Front = 2 };
const char* toString(CandidateFaces faces);
const char* toString(LineSpaceMode mode);
LineSpaceMode parseLineSpaceMode(const std::string& text); // "off|exact|shadow|candidate|candidate-exact-start"

class LineSpaceGpu {
public:
    // Requires a current GL context. Candidate pools and vertex normals are uploaded only when the Line
    // Spaces have candidates. Throws GlError when a pool exceeds the texture-buffer limit.
    LineSpaceGpu(const LineSpaces& spaces, const Bvh& bvh, const Scene& scene);

    void bind() const;
    // Defines for a traversal in `mode` (empty for Off). Candidate mode needs candidates. `faces`: which
    // candidate planes met from behind are no hit.
    std::vector<ShaderDefine> defines(LineSpaceMode mode, float maxNormalAngleDegrees,
                                      CandidateFaces faces = CandidateFaces::Both) const;
    bool hasCandidates() const { return hasCandidates_; }
    // Is any Line Space node a BVH leaf (a subtree below T triangles that ended the cut above depth D)?
    bool hasLeafSpaces() const { return hasLeafSpaces_; }
    uint64_t gpuBytes() const { return gpuBytes_; }
    uint32_t n() const { return n_; }

private:
    uint32_t n_ = 0;
    bool hasCandidates_ = false;
    bool hasLeafSpaces_ = false;
    TextureBuffer spaceOfNode_;
    TextureBuffer binaryWords_;
    TextureBuffer candidateWords_;
    TextureBuffer candidateOffsets_;
    TextureBuffer candidateData_;
    TextureBuffer vertexNormals_;
    uint64_t gpuBytes_ = 0;
};

// Octahedral encoding of a unit vector into two snorm16 (decoded by lsDecodeNormal in GLSL).
uint32_t encodeOctahedral(glm::vec3 n);

} // namespace chcrt::ls
