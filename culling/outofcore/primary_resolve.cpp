#include "culling/outofcore/primary_resolve.h"

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

// Map from the triangle ids hit in one subtree to their index in the subtree: open addressing with linear probing
// over two flat arrays. The resolve probes it once per triangle of the subtree (~43k for the 140M city), and with
// std::unordered_map's scattered nodes those probes were most of the resolve's time (docs/outofcore.md); here
// the ids of one subtree's pixels fit in the L2 cache.
class HitIdIndex {
public:
    static constexpr uint32_t kAbsent = UINT32_MAX;
    // Empties the map for up to `ids` distinct ids (load factor <= 1/2).
    void reset(size_t ids) {
        size_t capacity = 16;
        shift_ = 28;
        while (capacity < 2 * ids) {
            capacity *= 2;
            --shift_;
        }
        mask_ = capacity - 1;
        keys_.assign(capacity, CHCRT_NO_HIT_ID); // never a hit's id
        values_.assign(capacity, kAbsent);
        size_ = 0;
    }
    void insert(uint32_t id) {
        size_t i = slot(id);
        while (keys_[i] != CHCRT_NO_HIT_ID) {
            if (keys_[i] == id) return;
            i = (i + 1) & mask_;
        }
        keys_[i] = id;
        ++size_;
    }
    // The value slot of `id`, nullptr when it was not inserted.
    uint32_t* find(uint32_t id) {
        for (size_t i = slot(id);; i = (i + 1) & mask_) {
            if (keys_[i] == id) return &values_[i];
            if (keys_[i] == CHCRT_NO_HIT_ID) return nullptr;
        }
    }
    size_t size() const { return size_; }

private:
    // Fibonacci hashing: the top bits of id × 2^32/φ spread the clustered ids of a subtree over the table.
    size_t slot(uint32_t id) const { return size_t((id * 0x9E3779B1u) >> shift_); }
    std::vector<uint32_t> keys_, values_;
    size_t mask_ = 0, size_ = 0;
    int shift_ = 28; // 32 - log2(capacity)
};

} // namespace

PrimaryResolve::PrimaryResolve(OutOfCoreTracer& tracer, uint64_t denseSpanFactor)
    : tracer_(tracer), denseSpanFactor_(denseSpanFactor),
      program_({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                {GL_FRAGMENT_SHADER, "outofcore/gbuffer_from_pixel_attributes.frag.glsl"}}) {
    for (const ChsMaterialRecord& m : tracer.file().materials()) albedos_.emplace_back(m.baseColor[0], m.baseColor[1], m.baseColor[2]);
    if (albedos_.empty()) albedos_.emplace_back(glm::vec3(Material{}.baseColorFactor));
    tracer_.setRecordPrimarySubtrees(true);
}

PrimaryResolve::~PrimaryResolve() { tracer_.setRecordPrimarySubtrees(false); }

uint32_t PrimaryResolve::DenseIdIndex::find(uint32_t id) const {
    const uint32_t offset = id - first; // wraps for ids below `first`
    return offset < localOf.size() ? localOf[offset] : UINT32_MAX;
}

// Most subtrees of a prepared scene hold a compact range of original ids (the streamed city's: span within 1-3×
// the triangle count), so one table lookup per pixel replaces a scan of the whole subtree each frame (~45k triangles
// per subtree, ~190 hit subtrees per near frame of the 140M city). Tables of other subtrees are not built.
const PrimaryResolve::DenseIdIndex* PrimaryResolve::denseIndexFor(uint64_t subtree, const SubtreeData& data) {
    ++useClock_;
    if (const auto it = denseIndex_.find(subtree); it != denseIndex_.end()) {
        it->second.lastUse = useClock_;
        return it->second.localOf.empty() ? nullptr : &it->second;
    }
    DenseIdIndex index;
    index.lastUse = useClock_;
    uint32_t lo = UINT32_MAX, hi = 0;
    const size_t triangleCount = data.triangleCount();
    for (size_t k = 0; k < triangleCount; ++k) {
        lo = std::min(lo, data.originalId(k));
        hi = std::max(hi, data.originalId(k));
    }
    if (triangleCount != 0 && uint64_t(hi - lo) + 1 <= denseSpanFactor_ * uint64_t(triangleCount)) {
        index.first = lo;
        index.localOf.assign(size_t(hi - lo) + 1, UINT32_MAX);
        for (uint32_t k = 0; k < triangleCount; ++k) index.localOf[data.originalId(k) - lo] = k;
        denseBytes_ += index.localOf.size() * sizeof(uint32_t);
    }
    // Keep the tables within their budget: least recently used first (a few hundred entries at most).
    while (denseBytes_ > kDenseBudgetBytes && !denseIndex_.empty()) {
        auto oldest = denseIndex_.begin();
        for (auto it = denseIndex_.begin(); it != denseIndex_.end(); ++it) {
            if (it->second.lastUse < oldest->second.lastUse) oldest = it;
        }
        denseBytes_ -= oldest->second.localOf.size() * sizeof(uint32_t);
        denseIndex_.erase(oldest);
    }
    const auto [it, inserted] = denseIndex_.emplace(subtree, std::move(index));
    (void)inserted;
    return it->second.localOf.empty() ? nullptr : &it->second;
}

// The triangles (and their normals) that the pixels of `pixels` hit in subtree `subtree`, each distinct one read once
// from the file, and for each pixel the position of its triangle among them; false when they cannot be (a blob not
// verified in the file's current state, an index out of the pool, or one whose triangle has another id than the
// pixel's hit: a pixel whose hit a cell pass changed, which does not write the image).
bool PrimaryResolve::resolveByTriangles(uint32_t subtree, const std::vector<uint32_t>& pixels,
                                        std::vector<TriangleGpu>& triangles, std::vector<glm::vec3>& normals,
                                        std::vector<uint32_t>& triangleOfPixel) {
    std::vector<uint32_t>& indices = hitIndices_;
    indices.clear();
    for (uint32_t p : pixels) indices.push_back(pixelTriangles_[p]);
    std::sort(indices.begin(), indices.end());
    indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
    std::vector<uint32_t>& locals = hitLocals_;
    locals.resize(indices.size());
    for (size_t i = 0; i < indices.size(); ++i) {
        locals[i] = tracer_.cache().localTriangleOf(indices[i]);
        if (locals[i] == UINT32_MAX) return false;
    }
    triangles.resize(indices.size());
    normals.resize(indices.size() * 3);
    if (!tracer_.file().readTriangles(subtree, locals, triangles.data(), normals.data())) return false;
    stats_.trianglesRead += indices.size();
    triangleOfPixel.resize(pixels.size());
    for (size_t i = 0; i < pixels.size(); ++i) {
        const uint32_t p = pixels[i];
        const auto k = uint32_t(std::lower_bound(indices.begin(), indices.end(), pixelTriangles_[p]) - indices.begin());
        if (triangles[k].originalId != hits_[p].y) return false;
        triangleOfPixel[i] = k;
    }
    return true;
}

void PrimaryResolve::resolve(const Camera& camera, const FrameTargets& t, float nearPlane) {
    const auto start = std::chrono::steady_clock::now();
    stats_ = {};
    const int w = t.width, h = t.height;
    const size_t n = size_t(w) * size_t(h);
    // Frame-sized buffers are kept across frames: fresh ones cost page faults on every frame.
    std::vector<glm::uvec4>& hits = hits_;
    hits.resize(n);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGetTextureImage(t.hits[0].hit.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(n * sizeof(glm::uvec4)), hits.data());
    pixelSubtrees_ = tracer_.chcrt().readDebugImage(); // 1 + subtree, 0 = none
    const std::vector<uint32_t>& subtreeOf = pixelSubtrees_;
    const bool haveSubtrees = subtreeOf.size() == n;
    pixelTriangles_ = tracer_.chcrt().readHitTriangleImage(); // buffer index of the hit triangle (checked below)
    const bool haveTriangles = pixelTriangles_.size() == n;

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
    std::vector<glm::vec4>&shading = shadingRgba_, &geometric = geometricRgba_, &albedo = albedoRgba_;
    for (std::vector<glm::vec4>* image : {&shading, &geometric, &albedo}) image->assign(n, glm::vec4(0.0f));
    SubtreeStore& store = tracer_.store();
    // Shading terms of a pixel from its triangle and the triangle's 3 vertex normals. Neighbouring pixels mostly hit
    // the same triangle: the per-triangle terms are computed once per run of them.
    uint32_t lastTriangle = HitIdIndex::kAbsent;
    glm::vec3 g(0.0f), q0(0.0f), q1(0.0f), q2(0.0f);
    glm::vec4 triangleAlbedo(0.0f);
    const auto shadePixel = [&](uint32_t p, uint32_t triangleKey, const TriangleGpu& tri, const glm::vec3* normals) {
        if (triangleKey != lastTriangle) {
            lastTriangle = triangleKey;
            g = glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
            const float length = glm::length(g);
            g = length > 0.0f ? g / length : glm::vec3(0.0f, 1.0f, 0.0f);
            q0 = quantizedNormal(normals[0]);
            q1 = quantizedNormal(normals[1]);
            q2 = quantizedNormal(normals[2]);
            triangleAlbedo = glm::vec4(albedos_[std::min<size_t>(tri.materialId, albedos_.size() - 1)], 1.0f);
        }
        glm::vec2 b;
        std::memcpy(&b, &hits[p].z, sizeof(b));
        const float w0 = 1.0f - b.x - b.y;
        const glm::vec3 s = w0 * q0 + b.x * q1 + b.y * q2;
        const float sl = glm::length(s);
        shading[p] = glm::vec4(sl > 0.0f ? s / sl : g, 0.0f);
        geometric[p] = glm::vec4(g, 0.0f);
        albedo[p] = triangleAlbedo;
    };
    HitIdIndex localOf; // hit triangle id -> its index in the subtree
    std::vector<TriangleGpu> triangles;
    std::vector<glm::vec3> normals;
    std::vector<uint32_t> triangleOfPixel;
    for (const auto& [subtree, pixels] : pixelsOf) {
        ++stats_.subtreesRead;
        // chcrt-lod: the level the cache served this subtree at for this frame's camera (the primary trace's), whose
        // proxy triangles carry representative ids, their own normals and materials.
        const uint32_t level = tracer_.cache().levelFor(subtree);
        // A subtree the store does not hold whole: read only the triangles its pixels hit, found through the hit
        // triangle image (far views: ~2,800 subtrees of ~7 MB for ~80 pixels each). Each index must name a triangle
        // with the pixel's hit id, else the subtree is read whole as before.
        if (level == 0 && haveTriangles && !store.holdsAttributes(subtree, level) &&
            resolveByTriangles(subtree, pixels, triangles, normals, triangleOfPixel)) {
            ++stats_.subtreesByTriangles;
            lastTriangle = HitIdIndex::kAbsent;
            for (size_t i = 0; i < pixels.size(); ++i) {
                const uint32_t k = triangleOfPixel[i];
                shadePixel(pixels[i], k, triangles[k], &normals[size_t(k) * 3]);
            }
            continue;
        }
        const std::shared_ptr<const SubtreeData> data = store.get(subtree, level);
        const DenseIdIndex* dense = denseIndexFor(uint64_t(level) << 32 | subtree, *data);
        ++(dense ? stats_.subtreesIndexed : stats_.subtreesScanned);
        if (!dense) { // ids spread out: find the hit ones with one scan of the subtree
            localOf.reset(pixels.size());
            for (uint32_t p : pixels) localOf.insert(hits[p].y);
            size_t found = 0;
            for (uint32_t k = 0; k < data->triangleCount() && found < localOf.size(); ++k) {
                uint32_t* local = localOf.find(data->originalId(k));
                if (local && *local == HitIdIndex::kAbsent) {
                    *local = k;
                    ++found;
                }
            }
        }
        lastTriangle = HitIdIndex::kAbsent;
        for (uint32_t p : pixels) {
            const uint32_t k = dense ? dense->find(hits[p].y) : *localOf.find(hits[p].y);
            if (k == HitIdIndex::kAbsent) {
                ++stats_.unresolvedPixels;
                continue;
            }
            shadePixel(p, k, data->triangle(k), &data->normals[size_t(k) * 3]);
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
