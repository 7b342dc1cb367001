#include "linespace/linespace_gpu.h"

#include "linespace/shaft_index.h"
#include "renderer/core/error.h"
#include "shaders/shared/linespace_bindings.h"

#include <glm/gtc/packing.hpp>

#include <cmath>
#include <cstdio>

namespace chcrt::ls {
namespace {

// GL refuses a zero-sized buffer: upload one dummy word for an empty pool.
TextureBuffer uploadWords(const std::vector<uint32_t>& words, GLenum format = GL_R32UI) {
    static const uint32_t dummy[4] = {0, 0, 0, 0};
    if (words.empty()) return createTextureBuffer(dummy, sizeof(dummy), format);
    return createTextureBuffer(words.data(), words.size() * sizeof(uint32_t), format);
}

} // namespace

const char* toString(LineSpaceMode mode) {
    switch (mode) {
    case LineSpaceMode::Off: return "off";
    case LineSpaceMode::Exact: return "exact";
    case LineSpaceMode::Shadow: return "shadow";
    case LineSpaceMode::Candidate: return "candidate";
    case LineSpaceMode::CandidateExactStart: return "candidate-exact-start";
    }
    return "?";
}

const char* toString(CandidateFaces faces) {
    switch (faces) {
    case CandidateFaces::Both: return "both";
    case CandidateFaces::FrontInStartNode: return "front-start";
    case CandidateFaces::Front: return "front";
    }
    return "?";
}

LineSpaceMode parseLineSpaceMode(const std::string& text) {
    for (LineSpaceMode m : {LineSpaceMode::Off, LineSpaceMode::Exact, LineSpaceMode::Shadow, LineSpaceMode::Candidate,
                            LineSpaceMode::CandidateExactStart}) {
        if (text == toString(m)) return m;
    }
    throw InputError("unknown Line Space mode '" + text + "' (off, exact, shadow, candidate, candidate-exact-start)");
}

uint32_t encodeOctahedral(glm::vec3 n) {
    const float sum = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    if (!(sum > 0.0f)) return glm::packSnorm2x16(glm::vec2(0.0f, 0.0f)); // decodes to +z; never used for rejection
    n /= sum;
    glm::vec2 e(n.x, n.y);
    if (n.z < 0.0f) {
        e = (1.0f - glm::abs(glm::vec2(n.y, n.x))) * glm::vec2(n.x >= 0.0f ? 1.0f : -1.0f, n.y >= 0.0f ? 1.0f : -1.0f);
    }
    return glm::packSnorm2x16(e);
}

LineSpaceGpu::LineSpaceGpu(const LineSpaces& spaces, const Bvh& bvh, const Scene& scene)
    : n_(spaces.params.n), hasCandidates_(spaces.params.candidates && spaces.candidates.shaftsPerSpace() > 0) {
    if (spaces.spaceOfBvhNode.size() != bvh.nodes.size()) {
        throw InputError("Line Spaces were built for another BVH (" + std::to_string(spaces.spaceOfBvhNode.size()) +
                         " vs " + std::to_string(bvh.nodes.size()) + " nodes)");
    }
    for (uint32_t node : spaces.bvhNodes) hasLeafSpaces_ = hasLeafSpaces_ || bvh.isLeaf(node);
    spaceOfNode_ = uploadWords(spaces.spaceOfBvhNode);
    binaryWords_ = uploadWords(spaces.binaryWords);
    gpuBytes_ = spaceOfNode_.bytes + binaryWords_.bytes;
    if (hasCandidates_) {
        candidateWords_ = uploadWords(spaces.candidates.words());
        candidateOffsets_ = uploadWords(spaces.candidates.offsets());
        candidateData_ = uploadWords(spaces.candidates.data());
        // Per BVH-order triangle: the three vertex normals and their mean (RC §3.1 normal-angle rejection),
        // as intersectCandidatePlane reads them from the scene.
        std::vector<uint32_t> normals(bvh.triangles.size() * 4);
        for (size_t i = 0; i < bvh.triangles.size(); ++i) {
            const glm::uvec3 idx = scene.triangles[bvh.triangles[i].originalId];
            const glm::vec3 n0 = scene.normals[idx.x], n1 = scene.normals[idx.y], n2 = scene.normals[idx.z];
            const glm::vec3 mean = n0 + n1 + n2;
            normals[4 * i + 0] = encodeOctahedral(n0);
            normals[4 * i + 1] = encodeOctahedral(n1);
            normals[4 * i + 2] = encodeOctahedral(n2);
            normals[4 * i + 3] = encodeOctahedral(mean);
        }
        vertexNormals_ = uploadWords(normals, GL_RGBA32UI);
        gpuBytes_ += candidateWords_.bytes + candidateOffsets_.bytes + candidateData_.bytes + vertexNormals_.bytes;
    }
}

void LineSpaceGpu::bind() const {
    glBindTextureUnit(CHCRT_UNIT_LS_SPACE_OF_NODE, spaceOfNode_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_LS_BINARY_WORDS, binaryWords_.texture.id());
    if (hasCandidates_) {
        glBindTextureUnit(CHCRT_UNIT_LS_CANDIDATE_WORDS, candidateWords_.texture.id());
        glBindTextureUnit(CHCRT_UNIT_LS_CANDIDATE_OFFSETS, candidateOffsets_.texture.id());
        glBindTextureUnit(CHCRT_UNIT_LS_CANDIDATE_DATA, candidateData_.texture.id());
        glBindTextureUnit(CHCRT_UNIT_LS_VERTEX_NORMALS, vertexNormals_.texture.id());
    }
}

std::vector<ShaderDefine> LineSpaceGpu::defines(LineSpaceMode mode, float maxNormalAngleDegrees,
                                                CandidateFaces faces) const {
    if (mode == LineSpaceMode::Off) return {};
    const bool candidate = mode == LineSpaceMode::Candidate || mode == LineSpaceMode::CandidateExactStart;
    if (candidate && !hasCandidates_) {
        throw InputError("Line Space candidate mode needs Line Spaces built with candidates");
    }
    char cosText[64];
    std::snprintf(cosText, sizeof(cosText), "%.9g", std::cos(double(maxNormalAngleDegrees) * 3.14159265358979323846 / 180.0));
    std::string cosValue = cosText;
    if (cosValue.find_first_of(".e") == std::string::npos) cosValue += ".0";
    return {{"CHCRT_BVH_TRAVERSAL", "\"linespace/linespace_traverse.glsl\""}, // replaces the pure traversal
            {"CHCRT_LS_MODE", std::to_string(candidate ? int(LineSpaceMode::Candidate) : int(mode))},
            {"CHCRT_LS_CANDIDATE_START_EXACT", mode == LineSpaceMode::CandidateExactStart ? "1" : "0"},
            {"CHCRT_LS_CANDIDATE_FRONT_ONLY", std::to_string(candidate ? int(faces) : 0)},
            {"CHCRT_LS_N", std::to_string(n_) + "u"},
            {"CHCRT_LS_BINARY_WORDS_PER_SPACE", std::to_string(lsWordCount(n_, true)) + "u"},
            {"CHCRT_LS_CANDIDATE_WORDS_PER_SPACE", std::to_string(lsWordCount(n_, false)) + "u"},
            {"CHCRT_LS_COS_MAX_ANGLE", cosValue}};
}

} // namespace chcrt::ls
