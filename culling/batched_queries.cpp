#include "culling/batched_queries.h"

#include "shaders/shared/culling_layout.h"

#include <algorithm>
#include <cstring>

namespace chcrt {

namespace {

glm::uvec4 floatBits(const glm::vec3& v) {
    glm::uvec4 bits(0u);
    std::memcpy(&bits, &v, sizeof(v));
    return bits;
}

} // namespace

BatchedQueries::BatchedQueries() {
    program(false, false);
    program(true, false);
}

const ShaderProgram& BatchedQueries::program(bool anyHit, bool debugOverdraw) {
    ShaderProgram& program = programs_[anyHit ? 1 : 0][debugOverdraw ? 1 : 0];
    if (!program.valid()) {
        std::vector<ShaderDefine> defines = {{"TRACE_ANY_HIT", anyHit ? "1" : "0"}};
        if (debugOverdraw) defines.push_back({"CHCRT_CULLING_DEBUG_OVERDRAW", "1"});
        program = ShaderProgram({{GL_COMPUTE_SHADER, "culling/chcrt_query_batch.comp.glsl"}}, defines);
    }
    return program;
}

void BatchedQueries::test(const std::vector<Query>& queries, bool anyHit, uint32_t visibleThreshold,
                          bool debugOverdraw, std::vector<uint32_t>& counts) {
    counts.assign(queries.size(), 0u);
    if (queries.empty()) return;
    // The input: the pairs' records, then one work item per CHCRT_CULLING_BATCH_ITEM pixels of each pair's tile.
    staging_.clear();
    for (const Query& q : queries) {
        staging_.emplace_back(uint32_t(q.tile.x), uint32_t(q.tile.y), uint32_t(q.tile.width), uint32_t(q.tile.height));
        staging_.emplace_back(q.boxCount, 0u, 0u, 0u);
        for (int b = 0; b < 2; ++b) {
            staging_.push_back(floatBits(q.boxMin[b]));
            staging_.push_back(floatBits(q.boxMax[b]));
        }
    }
    const size_t itemBase = staging_.size();
    for (size_t i = 0; i < queries.size(); ++i) {
        const uint64_t pixels = uint64_t(queries[i].tile.area());
        for (uint64_t first = 0; first < pixels; first += CHCRT_CULLING_BATCH_ITEM) {
            staging_.emplace_back(uint32_t(i), uint32_t(first), 0u, 0u);
        }
    }
    const size_t items = staging_.size() - itemBase;
    if (staging_.size() > inputCapacity_) {
        inputCapacity_ = std::max(staging_.size(), 2 * inputCapacity_);
        input_ = createBuffer(inputCapacity_ * sizeof(glm::uvec4), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (queries.size() > countCapacity_) {
        countCapacity_ = std::max(queries.size(), 2 * countCapacity_);
        counts_ = createBuffer(countCapacity_ * sizeof(uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(input_.id(), 0, GLsizeiptr(staging_.size() * sizeof(glm::uvec4)), staging_.data());
    const uint32_t zero = 0u;
    glClearNamedBufferSubData(counts_.id(), GL_R32UI, 0, GLsizeiptr(queries.size() * sizeof(uint32_t)),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    // The subtree passes before this round stored hits as images.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const ShaderProgram& pass = program(anyHit, debugOverdraw);
    pass.use();
    pass.set("visibleThreshold", visibleThreshold);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_BATCH_INPUT_BUFFER, input_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_BATCH_COUNTS_BUFFER, counts_.id());
    // At most 65,535 work groups per dispatch (the smallest GL_MAX_COMPUTE_WORK_GROUP_COUNT GL 4.5 allows).
    constexpr size_t kMaxGroups = 65535;
    for (size_t first = 0; first < items; first += kMaxGroups) {
        pass.set("itemBase", uint32_t(itemBase + first));
        glDispatchCompute(GLuint(std::min(kMaxGroups, items - first)), 1, 1);
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    // The round's one read-back (it waits for the dispatch).
    glGetNamedBufferSubData(counts_.id(), 0, GLsizeiptr(queries.size() * sizeof(uint32_t)), counts.data());
}

} // namespace chcrt
