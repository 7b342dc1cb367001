#include "renderer/outofcore/primary_resolve.h"

#include "renderer/render/camera_math.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace chcrt::outofcore {
namespace {

// The in-core pipeline stores vertex normals as 16-bit unorm (scene_gpu.cpp); quantizing the same way keeps the
// out-of-core G-buffer within float rounding of the in-core traced one.
glm::vec3 quantizedNormal(const glm::vec3& n) {
    glm::vec3 q;
    for (int c = 0; c < 3; ++c) {
        const float unorm = float(std::lround(std::clamp(n[c] * 0.5f + 0.5f, 0.0f, 1.0f) * 65535.0f));
        q[c] = unorm * (2.0f / 65535.0f) - 1.0f;
    }
    return q;
}

} // namespace

PrimaryResolve::PrimaryResolve(OutOfCoreTracer& tracer)
    : tracer_(tracer),
      program_({{GL_VERTEX_SHADER, "common/fullscreen.vert.glsl"},
                {GL_FRAGMENT_SHADER, "outofcore/gbuffer_from_pixel_attributes.frag.glsl"}}) {
    for (const ChsMaterialRecord& m : tracer.file().materials()) albedos_.emplace_back(m.baseColor[0], m.baseColor[1], m.baseColor[2]);
    if (albedos_.empty()) albedos_.emplace_back(glm::vec3(Material{}.baseColorFactor));
    tracer_.setRecordPrimarySubtrees(true);
}

PrimaryResolve::~PrimaryResolve() { tracer_.setRecordPrimarySubtrees(false); }

void PrimaryResolve::resolve(const Camera& camera, const FrameTargets& t, float nearPlane) {
    const auto start = std::chrono::steady_clock::now();
    stats_ = {};
    const int w = t.width, h = t.height;
    const size_t n = size_t(w) * size_t(h);
    std::vector<glm::uvec4> hits(n);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGetTextureImage(t.hits[0].hit.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(n * sizeof(glm::uvec4)), hits.data());
    pixelSubtrees_ = tracer_.chcrt().readDebugImage(); // 1 + subtree, 0 = none
    const std::vector<uint32_t>& subtreeOf = pixelSubtrees_;
    const bool haveSubtrees = subtreeOf.size() == n;

    // Group hit pixels by subtree, then scan each subtree once for the triangles its pixels hit.
    std::unordered_map<uint32_t, std::vector<uint32_t>> pixelsOf;
    for (uint32_t p = 0; p < n; ++p) {
        if (hits[p].y == CHCRT_NO_HIT_ID) continue;
        ++stats_.hitPixels;
        if (!haveSubtrees || subtreeOf[p] == 0) {
            ++stats_.unresolvedPixels;
            continue;
        }
        pixelsOf[subtreeOf[p] - 1].push_back(p);
    }
    std::vector<glm::vec4> shading(n, glm::vec4(0.0f)), geometric(n, glm::vec4(0.0f)), albedo(n, glm::vec4(0.0f));
    SubtreeStore& store = tracer_.store();
    std::unordered_map<uint32_t, uint32_t> localOf; // original id -> triangle index in the subtree
    for (const auto& [subtree, pixels] : pixelsOf) {
        ++stats_.subtreesRead;
        const std::shared_ptr<const SubtreeData> data = store.get(subtree);
        localOf.clear();
        for (uint32_t p : pixels) localOf.emplace(hits[p].y, UINT32_MAX);
        size_t found = 0;
        for (uint32_t k = 0; k < data->triangles.size() && found < localOf.size(); ++k) {
            const auto it = localOf.find(data->triangles[k].originalId);
            if (it != localOf.end() && it->second == UINT32_MAX) {
                it->second = k;
                ++found;
            }
        }
        for (uint32_t p : pixels) {
            const uint32_t k = localOf[hits[p].y];
            if (k == UINT32_MAX) {
                ++stats_.unresolvedPixels;
                continue;
            }
            const TriangleGpu& tri = data->triangles[k];
            glm::vec3 g = glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
            const float length = glm::length(g);
            g = length > 0.0f ? g / length : glm::vec3(0.0f, 1.0f, 0.0f);
            glm::vec2 b;
            std::memcpy(&b, &hits[p].z, sizeof(b));
            const float w0 = 1.0f - b.x - b.y;
            const glm::vec3 s = w0 * quantizedNormal(data->normals[k * 3]) + b.x * quantizedNormal(data->normals[k * 3 + 1]) +
                                b.y * quantizedNormal(data->normals[k * 3 + 2]);
            const float sl = glm::length(s);
            shading[p] = glm::vec4(sl > 0.0f ? s / sl : g, 0.0f);
            geometric[p] = glm::vec4(g, 0.0f);
            albedo[p] = glm::vec4(albedos_[std::min<size_t>(tri.materialId, albedos_.size() - 1)], 1.0f);
        }
    }
    if (width_ != w || height_ != h) {
        shading_ = createTexture2D(w, h, GL_RGBA32F);
        geometric_ = createTexture2D(w, h, GL_RGBA32F);
        albedo_ = createTexture2D(w, h, GL_RGBA32F);
        width_ = w;
        height_ = h;
    }
    glTextureSubImage2D(shading_.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, shading.data());
    glTextureSubImage2D(geometric_.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, geometric.data());
    glTextureSubImage2D(albedo_.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, albedo.data());
    stats_.hostMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    const CameraFrame frame = makeCameraFrame(camera, w, h);
    program_.use();
    program_.set("cameraPosition", frame.eye);
    program_.set("cameraForward", frame.forward);
    program_.set("nearPlane", nearPlane);
    glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.id());
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST); // depth is written through gl_FragDepth, which needs the test enabled
    glDepthFunc(GL_ALWAYS);
    glDisable(GL_BLEND);
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, t.rays[0].origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, t.rays[0].direction.id());
    glBindTextureUnit(CHCRT_UNIT_HIT, t.hits[0].hit.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_POSITION, shading_.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_NORMAL, geometric_.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_ALBEDO, albedo_.id());
    drawFullscreenTriangle();
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
}

} // namespace chcrt::outofcore
