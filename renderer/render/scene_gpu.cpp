#include "renderer/render/scene_gpu.h"

#include "renderer/core/error.h"
#include "renderer/gl/shader.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <cmath>
#include <vector>

namespace chcrt {
namespace {

// Vertex buffer layout of the G-buffer pass: interleaved position, normal, texcoord (32 bytes).
struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 texcoord;
};
static_assert(sizeof(Vertex) == 32);

// Base-colour textures differ in size; a texture array needs one size, so every texture is resampled
// (bilinear, in sRGB space: good enough for albedo) to the largest size present, capped to keep memory sane.
constexpr uint32_t kMaxTextureArraySide = 1024;

std::vector<uint8_t> resampleRgba8(const Texture& texture, uint32_t width, uint32_t height) {
    std::vector<uint8_t> out(size_t(width) * height * 4);
    for (uint32_t y = 0; y < height; ++y) {
        float sy = std::max(0.0f, (float(y) + 0.5f) * float(texture.height) / float(height) - 0.5f);
        uint32_t y0 = std::min(uint32_t(sy), texture.height - 1);
        uint32_t y1 = std::min(y0 + 1, texture.height - 1);
        float fy = sy - float(y0);
        for (uint32_t x = 0; x < width; ++x) {
            float sx = std::max(0.0f, (float(x) + 0.5f) * float(texture.width) / float(width) - 0.5f);
            uint32_t x0 = std::min(uint32_t(sx), texture.width - 1);
            uint32_t x1 = std::min(x0 + 1, texture.width - 1);
            float fx = sx - float(x0);
            for (int c = 0; c < 4; ++c) {
                auto at = [&](uint32_t px, uint32_t py) {
                    return float(texture.rgba8[(size_t(py) * texture.width + px) * 4 + c]);
                };
                float top = at(x0, y0) * (1 - fx) + at(x1, y0) * fx;
                float bottom = at(x0, y1) * (1 - fx) + at(x1, y1) * fx;
                out[(size_t(y) * width + x) * 4 + c] = uint8_t(std::lround(top * (1 - fy) + bottom * fy));
            }
        }
    }
    return out;
}

uint64_t maxTextureBufferTexels() {
    GLint texels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    return uint64_t(std::max(texels, 0));
}

// A per-triangle array of `count` elements of `texelsPerElement` texels (`elementBytes` bytes each) in as many texture
// buffers of at most `maxTexels` texels as it needs: every part holds the same whole number of elements but the
// last, which the shaders' part search relies on (render/triangle_parts.glsl).
std::vector<TextureBuffer> createParts(const char* what, const void* data, uint64_t count, size_t elementBytes,
                                       uint64_t texelsPerElement, GLenum format, uint64_t maxTexels) {
    const uint64_t perPart = std::max<uint64_t>(1, maxTexels / texelsPerElement);
    const uint64_t parts = std::max<uint64_t>(1, (count + perPart - 1) / perPart);
    if (parts > CHCRT_MAX_TRIANGLE_BUFFERS) {
        throw GlError("the scene's " + std::to_string(count) + " " + what + " need " + std::to_string(parts) +
                      " texture buffers of " + std::to_string(maxTexels) + " texels; chcrt reads at most " +
                      std::to_string(CHCRT_MAX_TRIANGLE_BUFFERS) + " (" + std::to_string(perPart * CHCRT_MAX_TRIANGLE_BUFFERS) +
                      " triangles in core; larger scenes render out of core, docs/outofcore.md)");
    }
    std::vector<TextureBuffer> buffers;
    for (uint64_t part = 0; part < parts; ++part) {
        const uint64_t first = part * perPart, n = std::min(perPart, count - std::min(count, first));
        buffers.push_back(createTextureBuffer(static_cast<const char*>(data) + first * elementBytes, n * elementBytes, format));
    }
    return buffers;
}

uint64_t bytesOf(const std::vector<TextureBuffer>& parts) {
    uint64_t bytes = 0;
    for (const TextureBuffer& part : parts) bytes += part.bytes;
    return bytes;
}

// Binds part 0 at `unit`, part k at firstPartUnit + k - 1.
void bindParts(const std::vector<TextureBuffer>& parts, GLuint unit, GLuint firstPartUnit) {
    for (size_t part = 0; part < parts.size(); ++part) {
        glBindTextureUnit(part == 0 ? unit : firstPartUnit + GLuint(part) - 1, parts[part].texture.id());
    }
}

} // namespace

SceneGpu::SceneGpu(const Scene& scene, const Bvh& bvh, uint64_t maxBufferTexels)
    : triangleCount_(scene.triangleCount()),
      maxBufferTexels_(maxBufferTexels != 0 ? std::min(maxBufferTexels, maxTextureBufferTexels()) : maxTextureBufferTexels()) {
    // The nodes stay in one buffer: CHC+RT's and the Line Space traversals read them directly.
    if (bvh.nodes.size() * CHCRT_BVH_TEXELS_PER_NODE > maxTextureBufferTexels()) {
        throw GlError("the scene's BVH has " + std::to_string(bvh.nodes.size()) + " nodes, more than one texture buffer of " +
                      std::to_string(maxTextureBufferTexels()) + " texels holds (" + std::to_string(CHCRT_BVH_TEXELS_PER_NODE) +
                      " per node); render it out of core (docs/outofcore.md) or with larger BVH leaves (--bvh-leaf-size)");
    }
    buildClusters(bvh);
    uploadGeometry(scene, bvh);
    bvhNodes_ = createTextureBuffer(bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNodeGpu), GL_RGBA32F);
    bvhTriangles_ = createParts("triangles", bvh.triangles.data(), bvh.triangles.size(), sizeof(TriangleGpu),
                                CHCRT_TRI_TEXELS_PER_TRIANGLE, GL_RGBA32F, maxBufferTexels_);
    uploadAttributes(scene);
    uploadMaterials(scene);
    gpuBytes_ += bvhNodes_.bytes + bytesOf(bvhTriangles_) + bytesOf(triangleAttributes_) + bytesOf(triangleNormals_) +
                 materials_.bytes;
    const int parts = triangleBufferCount();
    const std::string current = processShaderDefine("CHCRT_TRIANGLE_BUFFERS");
    if (parts > 1 && parts > (current.empty() ? 1 : std::stoi(current))) {
        setProcessShaderDefine("CHCRT_TRIANGLE_BUFFERS", std::to_string(parts));
    }
}

uint64_t SceneGpu::estimatedBytes(uint64_t triangles, uint64_t vertices, uint64_t nodes) {
    const uint64_t perTriangle = sizeof(TriangleGpu) + CHCRT_ATTR_TEXELS_PER_TRIANGLE * 16 +
                                 CHCRT_NORMAL_TEXELS_PER_TRIANGLE * 8 + sizeof(glm::uvec3); // + raster indices
    return triangles * perTriangle + vertices * sizeof(Vertex) + nodes * sizeof(BvhNodeGpu);
}

// Clusters for frustum culling: the topmost BVH nodes with at most kClusterTriangles triangles. Each node's
// triangles form one contiguous range of the BVH-ordered triangle array (ranges are checked, not assumed: a node
// whose children's ranges are not adjacent is split further).
void SceneGpu::buildClusters(const Bvh& bvh) {
    constexpr uint32_t kClusterTriangles = 1024;
    // Per node: triangle range [first, first + count) if contiguous, else count = UINT32_MAX.
    struct Range {
        uint32_t first = 0, count = 0;
    };
    std::vector<Range> ranges(bvh.nodes.size());
    for (size_t i = bvh.nodes.size(); i-- > 0;) {
        const BvhNodeGpu& node = bvh.nodes[i];
        if (node.triCount != 0) {
            ranges[i] = {node.leftFirst, node.triCount};
            continue;
        }
        const Range a = ranges[node.leftFirst], b = ranges[node.leftFirst + 1];
        const bool contiguous = a.count != UINT32_MAX && b.count != UINT32_MAX &&
                                (a.first + a.count == b.first || b.first + b.count == a.first);
        ranges[i] = contiguous ? Range{std::min(a.first, b.first), a.count + b.count} : Range{0, UINT32_MAX};
    }
    std::vector<uint32_t> stack = {0};
    while (!stack.empty()) {
        const uint32_t index = stack.back();
        stack.pop_back();
        const BvhNodeGpu& node = bvh.nodes[index];
        const Range range = ranges[index];
        if (node.triCount != 0 || (range.count != UINT32_MAX && range.count <= kClusterTriangles)) {
            Aabb bounds;
            bounds.lower = node.boundsMin;
            bounds.upper = node.boundsMax;
            clusters_.push_back({bounds, range.first, range.count});
        } else {
            stack.push_back(node.leftFirst + 1);
            stack.push_back(node.leftFirst);
        }
    }
}

void SceneGpu::uploadGeometry(const Scene& scene, const Bvh& bvh) {
    std::vector<Vertex> vertices(scene.positions.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        vertices[i].position = scene.positions[i];
        vertices[i].normal = scene.normals[i];
        vertices[i].texcoord = scene.texcoords.empty() ? glm::vec2(0.0f) : scene.texcoords[i];
    }
    vertexBuffer_ = createBuffer(vertices.size() * sizeof(Vertex), vertices.data(), 0);
    // Indices in BVH order, so that every cluster (BVH subtree) is one contiguous draw.
    std::vector<glm::uvec3> bvhOrderIndices(bvh.triangles.size());
    for (size_t k = 0; k < bvh.triangles.size(); ++k) bvhOrderIndices[k] = scene.triangles[bvh.triangles[k].originalId];
    indexBuffer_ = createBuffer(bvhOrderIndices.size() * sizeof(glm::uvec3), bvhOrderIndices.data(), 0);
    std::vector<uint32_t> clusterFirst(clusters_.size());
    for (size_t c = 0; c < clusters_.size(); ++c) clusterFirst[c] = clusters_[c].firstTriangle;
    clusterFirstBuffer_ = createBuffer(clusterFirst.size() * sizeof(uint32_t), clusterFirst.data(), 0);
    indirectBuffer_ = createBuffer(clusters_.size() * 5 * sizeof(uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
    gpuBytes_ += vertices.size() * sizeof(Vertex) + scene.triangles.size() * sizeof(glm::uvec3);
}

// Vertex array objects are container objects that GL contexts do not share (GL 4.5 §5.1.3), unlike the buffers
// they point to: the scene may be uploaded on a worker thread's shared context (the viewer), so the vertex array
// is made on the drawing context, on its first draw.
void SceneGpu::createVertexArrayForDrawing() {
    vertexArray_ = createVertexArray();
    const GLuint vao = vertexArray_.id();
    glVertexArrayVertexBuffer(vao, 0, vertexBuffer_.id(), 0, sizeof(Vertex));
    glVertexArrayElementBuffer(vao, indexBuffer_.id());
    const GLuint offsets[3] = {offsetof(Vertex, position), offsetof(Vertex, normal), offsetof(Vertex, texcoord)};
    const GLint sizes[3] = {3, 3, 2};
    for (GLuint attribute = 0; attribute < 3; ++attribute) {
        glEnableVertexArrayAttrib(vao, attribute);
        glVertexArrayAttribFormat(vao, attribute, sizes[attribute], GL_FLOAT, GL_FALSE, offsets[attribute]);
        glVertexArrayAttribBinding(vao, attribute, 0);
    }
    // Attribute 3: the cluster's first BVH-order triangle, one value per instance; each indirect command draws one
    // instance with baseInstance = its cluster index, so the shader sees that cluster's value.
    glVertexArrayVertexBuffer(vao, 1, clusterFirstBuffer_.id(), 0, sizeof(uint32_t));
    glVertexArrayBindingDivisor(vao, 1, 1);
    glEnableVertexArrayAttrib(vao, 3);
    glVertexArrayAttribIFormat(vao, 3, 1, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(vao, 3, 1);
}

void SceneGpu::uploadAttributes(const Scene& scene) {
    // Layout: CHCRT_ATTR_TEXELS_PER_TRIANGLE texels per original triangle id (render_layout.h).
    std::vector<glm::vec4> texels(scene.triangles.size() * CHCRT_ATTR_TEXELS_PER_TRIANGLE);
    // Vertex normals as 16-bit fixed point ((n * 0.5 + 0.5) * 65535): texture buffers have no snorm formats;
    // the error (3e-5) is far below what shading can show.
    std::vector<uint16_t> normals(scene.triangles.size() * CHCRT_NORMAL_TEXELS_PER_TRIANGLE * 4, 0);
    auto toUnorm16 = [](float v) {
        return uint16_t(std::lround(std::clamp(v * 0.5f + 0.5f, 0.0f, 1.0f) * 65535.0f));
    };
    const bool hasUv = !scene.texcoords.empty();
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::uvec3 tri = scene.triangles[i];
        const glm::vec3 p0 = scene.positions[tri.x], p1 = scene.positions[tri.y], p2 = scene.positions[tri.z];
        glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
        const float length = glm::length(n);
        n = length > 0.0f ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
        const uint32_t material = scene.triangleMaterials[i];
        float materialBits;
        std::memcpy(&materialBits, &material, sizeof(float));
        glm::vec2 uv0(0.0f), uv1(0.0f), uv2(0.0f);
        if (hasUv) {
            uv0 = scene.texcoords[tri.x];
            uv1 = scene.texcoords[tri.y];
            uv2 = scene.texcoords[tri.z];
        }
        // Texture-space scale: sqrt(uv area / world area), so that the traced G-buffer can choose the mip level
        // rasterisation's derivatives would (shaders/render/gbuffer_from_hits.frag.glsl).
        const float uvArea = std::abs((uv1.x - uv0.x) * (uv2.y - uv0.y) - (uv2.x - uv0.x) * (uv1.y - uv0.y));
        const float uvScale = length > 0.0f ? std::sqrt(uvArea / length) : 0.0f; // length = 2 × world area
        texels[i * 3 + 0] = glm::vec4(n, materialBits);
        texels[i * 3 + 1] = glm::vec4(uv0, uv1);
        texels[i * 3 + 2] = glm::vec4(uv2, uvScale, 0.0f);
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 vn = scene.normals[tri[k]];
            for (int c = 0; c < 3; ++c) normals[(i * 3 + k) * 4 + c] = toUnorm16(vn[c]);
        }
    }
    triangleAttributes_ = createParts("triangles' attributes", texels.data(), scene.triangles.size(),
                                      CHCRT_ATTR_TEXELS_PER_TRIANGLE * sizeof(glm::vec4), CHCRT_ATTR_TEXELS_PER_TRIANGLE,
                                      GL_RGBA32F, maxBufferTexels_);
    triangleNormals_ = createParts("triangles' vertex normals", normals.data(), scene.triangles.size(),
                                   CHCRT_NORMAL_TEXELS_PER_TRIANGLE * 4 * sizeof(uint16_t),
                                   CHCRT_NORMAL_TEXELS_PER_TRIANGLE, GL_RGBA16UI, maxBufferTexels_);
}

void SceneGpu::uploadMaterials(const Scene& scene) {
    // Texture array side: the largest texture, capped; each layer's uv scale maps [0,1] onto the whole layer.
    uint32_t side = 1;
    for (const Texture& texture : scene.textures) side = std::max({side, texture.width, texture.height});
    side = std::min(side, kMaxTextureArraySide);
    baseColorSide_ = side;
    const int layers = std::max<int>(1, int(scene.textures.size()));
    const int levels = 1 + int(std::floor(std::log2(float(side))));
    GLuint array = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array);
    baseColorArray_ = GlTexture(array);
    glTextureStorage3D(array, levels, GL_SRGB8_ALPHA8, GLsizei(side), GLsizei(side), layers);
    if (scene.textures.empty()) {
        const uint8_t white[4] = {255, 255, 255, 255};
        glTextureSubImage3D(array, 0, 0, 0, 0, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);
    }
    for (size_t layer = 0; layer < scene.textures.size(); ++layer) {
        const std::vector<uint8_t> pixels = resampleRgba8(scene.textures[layer], side, side);
        glTextureSubImage3D(array, 0, 0, 0, GLint(layer), GLsizei(side), GLsizei(side), 1, GL_RGBA,
                            GL_UNSIGNED_BYTE, pixels.data());
    }
    glGenerateTextureMipmap(array);
    glTextureParameteri(array, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(array, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(array, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(array, GL_TEXTURE_WRAP_T, GL_REPEAT);
    gpuBytes_ += uint64_t(side) * side * 4 * layers * 4 / 3;

    std::vector<glm::vec4> texels;
    texels.reserve(scene.materials.size() * CHCRT_MATERIAL_TEXELS);
    for (const Material& material : scene.materials) {
        texels.push_back(material.baseColorFactor);
        const float layer = material.baseColorTexture >= 0 ? float(material.baseColorTexture) : -1.0f;
        texels.emplace_back(layer, 1.0f, 1.0f, 0.0f);
    }
    materials_ = createTextureBuffer(texels.data(), texels.size() * sizeof(glm::vec4), GL_RGBA32F);
}

void SceneGpu::bindForTracing() const {
    glBindTextureUnit(CHCRT_UNIT_BVH_NODES, bvhNodes_.texture.id());
    bindParts(bvhTriangles_, CHCRT_UNIT_BVH_TRIANGLES, CHCRT_UNIT_BVH_TRIANGLES_PART1);
}

void SceneGpu::bindForShading() const {
    bindParts(triangleAttributes_, CHCRT_UNIT_TRI_ATTRIBUTES, CHCRT_UNIT_TRI_ATTRIBUTES_PART1);
    bindParts(triangleNormals_, CHCRT_UNIT_TRI_NORMALS, CHCRT_UNIT_TRI_NORMALS_PART1);
    glBindTextureUnit(CHCRT_UNIT_MATERIALS, materials_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_BASE_COLOR, baseColorArray_.id());
}

namespace {

// A box is outside when it lies entirely on the negative side of one frustum plane. With reversed infinite Z
// (camera_math.h) the clip volume is -w <= x, y <= w and 0 <= z <= w; z >= 0 holds everywhere in front of the
// camera's plane, so the planes are left, right, bottom, top and near (z <= w).
bool outsideFrustum(const glm::mat4& clipFromWorld, const Aabb& box) {
    const glm::mat4 m = glm::transpose(clipFromWorld); // rows of clipFromWorld as columns
    const glm::vec4 planes[5] = {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] - m[2]};
    for (const glm::vec4& plane : planes) {
        // The box corner furthest along the plane normal.
        const glm::vec3 corner(plane.x >= 0 ? box.upper.x : box.lower.x, plane.y >= 0 ? box.upper.y : box.lower.y,
                               plane.z >= 0 ? box.upper.z : box.lower.z);
        if (glm::dot(glm::vec3(plane), corner) + plane.w < 0.0f) return true;
    }
    return false;
}

} // namespace

uint64_t SceneGpu::drawTriangles(const glm::mat4& clipFromWorld, bool frustumCulling) {
    struct DrawElementsIndirectCommand {
        uint32_t count, instanceCount, firstIndex, baseVertex, baseInstance;
    };
    std::vector<DrawElementsIndirectCommand> commands;
    commands.reserve(clusters_.size());
    uint64_t triangles = 0;
    for (size_t c = 0; c < clusters_.size(); ++c) {
        const Cluster& cluster = clusters_[c];
        if (frustumCulling && outsideFrustum(clipFromWorld, cluster.bounds)) continue;
        commands.push_back({cluster.triangleCount * 3, 1, cluster.firstTriangle * 3, 0, uint32_t(c)});
        triangles += cluster.triangleCount;
    }
    if (commands.empty()) return 0;
    glNamedBufferSubData(indirectBuffer_.id(), 0, GLsizeiptr(commands.size() * sizeof(DrawElementsIndirectCommand)),
                         commands.data());
    if (vertexArray_.id() == 0) createVertexArrayForDrawing();
    glBindVertexArray(vertexArray_.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, indirectBuffer_.id());
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, nullptr, GLsizei(commands.size()), 0);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
    return triangles;
}

} // namespace chcrt
