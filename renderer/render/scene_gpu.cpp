#include "renderer/render/scene_gpu.h"

#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <cmath>
#include <vector>

namespace chcrt {
namespace {

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

} // namespace

SceneGpu::SceneGpu(const Scene& scene, const Bvh& bvh) : triangleCount_(scene.triangleCount()) {
    uploadGeometry(scene);
    bvhNodes_ = createTextureBuffer(bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNodeGpu), GL_RGBA32F);
    bvhTriangles_ =
        createTextureBuffer(bvh.triangles.data(), bvh.triangles.size() * sizeof(TriangleGpu), GL_RGBA32F);
    uploadAttributes(scene);
    uploadMaterials(scene);
    gpuBytes_ += bvhNodes_.bytes + bvhTriangles_.bytes + triangleAttributes_.bytes + materials_.bytes;
}

void SceneGpu::uploadGeometry(const Scene& scene) {
    // Interleaved position, normal, texcoord: 32 bytes per vertex.
    struct Vertex {
        glm::vec3 position;
        glm::vec3 normal;
        glm::vec2 texcoord;
    };
    static_assert(sizeof(Vertex) == 32);
    std::vector<Vertex> vertices(scene.positions.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        vertices[i].position = scene.positions[i];
        vertices[i].normal = scene.normals[i];
        vertices[i].texcoord = scene.texcoords.empty() ? glm::vec2(0.0f) : scene.texcoords[i];
    }
    vertexBuffer_ = createBuffer(vertices.size() * sizeof(Vertex), vertices.data(), 0);
    indexBuffer_ = createBuffer(scene.triangles.size() * sizeof(glm::uvec3), scene.triangles.data(), 0);
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
    gpuBytes_ += vertices.size() * sizeof(Vertex) + scene.triangles.size() * sizeof(glm::uvec3);
}

void SceneGpu::uploadAttributes(const Scene& scene) {
    // Layout: CHCRT_ATTR_TEXELS_PER_TRIANGLE texels per original triangle id (render_layout.h).
    std::vector<glm::vec4> texels(scene.triangles.size() * CHCRT_ATTR_TEXELS_PER_TRIANGLE);
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
        texels[i * 3 + 0] = glm::vec4(n, materialBits);
        texels[i * 3 + 1] = glm::vec4(uv0, uv1);
        texels[i * 3 + 2] = glm::vec4(uv2, 0.0f, 0.0f);
    }
    triangleAttributes_ = createTextureBuffer(texels.data(), texels.size() * sizeof(glm::vec4), GL_RGBA32F);
}

void SceneGpu::uploadMaterials(const Scene& scene) {
    // Texture array side: the largest texture, capped; each layer's uv scale maps [0,1] onto the whole layer.
    uint32_t side = 1;
    for (const Texture& texture : scene.textures) side = std::max({side, texture.width, texture.height});
    side = std::min(side, kMaxTextureArraySide);
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
    glBindTextureUnit(CHCRT_UNIT_BVH_TRIANGLES, bvhTriangles_.texture.id());
}

void SceneGpu::bindForShading() const {
    glBindTextureUnit(CHCRT_UNIT_TRI_ATTRIBUTES, triangleAttributes_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_MATERIALS, materials_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_BASE_COLOR, baseColorArray_.id());
}

void SceneGpu::drawTriangles() const {
    glBindVertexArray(vertexArray_.id());
    glDrawElements(GL_TRIANGLES, GLsizei(triangleCount_ * 3), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

} // namespace chcrt
