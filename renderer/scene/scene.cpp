#include "renderer/scene/scene.h"

#include "renderer/core/error.h"
#include "renderer/scene/mesh_utils.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace chcrt {

Aabb Scene::bounds() const {
    // Over all positions (not only referenced ones): one linear pass, and loaders keep few unused vertices.
    Aabb box;
    for (const glm::vec3& p : positions) box.grow(p);
    return box;
}

namespace {

bool isFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void checkArraySizes(const Scene& scene) {
    if (scene.normals.size() != scene.positions.size())
        throw InputError("scene has " + std::to_string(scene.normals.size()) + " normals for " +
                         std::to_string(scene.positions.size()) + " vertices");
    if (!scene.texcoords.empty() && scene.texcoords.size() != scene.positions.size())
        throw InputError("scene has " + std::to_string(scene.texcoords.size()) + " texture coordinates for " +
                         std::to_string(scene.positions.size()) + " vertices");
    if (scene.triangleMaterials.size() != scene.triangles.size())
        throw InputError("scene has " + std::to_string(scene.triangleMaterials.size()) + " triangle materials for " +
                         std::to_string(scene.triangles.size()) + " triangles");
}

void checkMaterialsAndTextures(const Scene& scene) {
    if (scene.materials.empty()) throw InputError("scene has no materials");
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const int32_t texture = scene.materials[i].baseColorTexture;
        if (texture < -1 || texture >= static_cast<int32_t>(scene.textures.size()))
            throw InputError("material " + std::to_string(i) + " refers to missing texture " + std::to_string(texture));
    }
    for (size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& t = scene.textures[i];
        if (t.width == 0 || t.height == 0 || t.rgba8.size() != size_t(t.width) * t.height * 4)
            throw InputError("texture " + std::to_string(i) + " ('" + t.name + "') has inconsistent size");
    }
    for (size_t i = 0; i < scene.triangleMaterials.size(); ++i) {
        if (scene.triangleMaterials[i] >= scene.materials.size())
            throw InputError("triangle " + std::to_string(i) + " refers to missing material " +
                             std::to_string(scene.triangleMaterials[i]));
    }
}

} // namespace

void validateScene(const Scene& scene) {
    if (scene.triangles.empty()) throw InputError("scene has no triangles");
    checkArraySizes(scene);
    for (size_t i = 0; i < scene.positions.size(); ++i) {
        if (!isFinite(scene.positions[i]))
            throw InputError("vertex " + std::to_string(i) + " has a non-finite position " +
                             detail::formatVec3(scene.positions[i]));
        if (!isFinite(scene.normals[i]))
            throw InputError("vertex " + std::to_string(i) + " has a non-finite normal " +
                             detail::formatVec3(scene.normals[i]));
    }
    const size_t vertexCount = scene.positions.size();
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::uvec3& t = scene.triangles[i];
        if (t.x >= vertexCount || t.y >= vertexCount || t.z >= vertexCount)
            throw InputError("triangle " + std::to_string(i) + " has a vertex index out of range (" +
                             std::to_string(vertexCount) + " vertices)");
    }
    checkMaterialsAndTextures(scene);
}

void generateVertexNormals(Scene& scene) {
    scene.normals = detail::computeVertexNormals(scene.positions, scene.triangles);
}

void dropDegenerateTriangles(Scene& scene) {
    std::vector<uint32_t>* materials =
        scene.triangleMaterials.size() == scene.triangles.size() ? &scene.triangleMaterials : nullptr;
    scene.stats.degenerateTrianglesDropped += detail::removeDegenerateTriangles(scene.positions, scene.triangles, materials);
    scene.stats.instancedTriangles = scene.triangles.size();
}

namespace {

// The box of the middle 90 % of the triangles along each axis (5th to 95th percentile of their centroids; at most
// ~1M centroids, evenly strided): where the scene's detail is, without a terrain's skirt, a cliff or a sky.
Aabb denseBox(const Scene& scene) {
    const size_t n = scene.triangles.size();
    const size_t stride = std::max<size_t>(1, n / (size_t(1) << 20));
    std::array<std::vector<float>, 3> axes;
    for (auto& a : axes) a.reserve(n / stride + 1);
    for (size_t i = 0; i < n; i += stride) {
        const glm::uvec3& t = scene.triangles[i];
        const glm::vec3 c = (scene.positions[t.x] + scene.positions[t.y] + scene.positions[t.z]) / 3.0f;
        for (int a = 0; a < 3; ++a) axes[size_t(a)].push_back(c[a]);
    }
    Aabb box;
    for (int a = 0; a < 3; ++a) {
        std::vector<float>& v = axes[size_t(a)];
        const size_t lo = v.size() / 20, hi = v.size() - 1 - v.size() / 20;
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(lo), v.end());
        box.lower[a] = v[lo];
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(hi), v.end());
        box.upper[a] = v[hi];
    }
    return box;
}

} // namespace

// The bounding sphere of the box (centre, half its diagonal) fits the vertical field of view when the eye is
// at distance r / sin(fovY / 2); a 5 % margin keeps silhouettes off the image border. Viewing from the front
// (+Z) and 25 degrees above shows tops and fronts, the usual hero view for +Y-up scenes. With an aspect
// ratio >= 1 the horizontal field of view is wider, so the vertical one is the binding constraint.
//
// A large, open scene (a town, a castle's streets: kLargeSceneTriangles or more, and its dense part flat, less high
// than a quarter of its horizontal extent) framed so would be a small island seen from far outside the bounds
// (the Intel castle: its cliff reaches 105 m below the town, which is 12 m high). Its default camera stands inside
// the bounds instead, at the front (+Z) edge of the dense part and above it (up to the top of the bounds, the
// 25° elevation when there is room), and looks at the dense part's centre.
Camera defaultCamera(const Scene& scene, float fovYDegrees) {
    const Aabb box = scene.bounds();
    constexpr size_t kLargeSceneTriangles = 100000;
    if (!box.empty() && scene.triangles.size() >= kLargeSceneTriangles) {
        const Aabb dense = denseBox(scene);
        const glm::vec3 extent = dense.upper - dense.lower;
        const float horizontal = std::sqrt(extent.x * extent.x + extent.z * extent.z);
        if (horizontal > 0.0f && extent.y < 0.25f * horizontal && extent.z > 0.0f) {
            Camera camera;
            camera.target = dense.center();
            const float back = 0.5f * extent.z; // to the dense part's front edge
            const float rise = std::min(back * std::tan(glm::radians(25.0f)), box.upper.y - camera.target.y);
            camera.eye = glm::vec3(camera.target.x, camera.target.y + std::max(rise, 0.0f), dense.upper.z);
            camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
            camera.fovYDegrees = fovYDegrees;
            return camera;
        }
    }
    const glm::vec3 center = box.empty() ? glm::vec3(0.0f) : box.center();
    float radius = 0.5f * box.diagonal();
    if (!(radius > 0.0f)) radius = 1.0f;
    const float halfFov = 0.5f * glm::radians(std::clamp(fovYDegrees, 1.0f, 179.0f));
    const float distance = 1.05f * radius / std::sin(halfFov);
    const float elevation = glm::radians(25.0f);
    const glm::vec3 direction(0.0f, std::sin(elevation), std::cos(elevation));
    Camera camera;
    camera.eye = center + distance * direction;
    camera.target = center;
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.fovYDegrees = fovYDegrees;
    return camera;
}

// Radiance choice: a white Lambertian plane at the bottom of the bounds, at the point below the bounds'
// centre, should reflect an outgoing radiance of kTargetRadiance = 0.8 from this light alone (bright but not
// clipped at exposure 1; the default 0.8 grey then reflects 0.64). The reflected radiance is E / pi with
// irradiance E = L * G, G = integral over the light of cos(theta_light) cos(theta_plane) / r^2 dA, so
// L = kTargetRadiance * pi / G. G is integrated numerically (midpoint rule) because the light is not small
// against its distance for flat scenes.
namespace {

float lightGeometryFactor(const AreaLight& light, const glm::vec3& receiver, const glm::vec3& receiverNormal) {
    constexpr int kSteps = 16;
    const glm::vec3 lightNormal = light.normal();
    const float cellArea = light.area() / float(kSteps * kSteps);
    float sum = 0.0f;
    for (int i = 0; i < kSteps; ++i) {
        for (int j = 0; j < kSteps; ++j) {
            const glm::vec3 point = light.corner + ((i + 0.5f) / kSteps) * light.edgeU + ((j + 0.5f) / kSteps) * light.edgeV;
            const glm::vec3 toLight = point - receiver;
            const float distanceSquared = glm::dot(toLight, toLight);
            const glm::vec3 direction = toLight / std::sqrt(distanceSquared);
            const float cosReceiver = std::max(0.0f, glm::dot(direction, receiverNormal));
            const float cosLight = std::max(0.0f, -glm::dot(direction, lightNormal));
            sum += cosReceiver * cosLight / distanceSquared * cellArea;
        }
    }
    return sum;
}

} // namespace

AreaLight defaultAreaLight(const Scene& scene) {
    constexpr float kTargetRadiance = 0.8f;
    const Aabb box = scene.bounds();
    const glm::vec3 lower = box.empty() ? glm::vec3(-1.0f) : box.lower;
    const glm::vec3 upper = box.empty() ? glm::vec3(1.0f) : box.upper;
    const glm::vec3 extent = upper - lower;
    const glm::vec3 center = 0.5f * (lower + upper);
    float horizontal = std::max(extent.x, extent.z);
    if (!(horizontal > 0.0f)) horizontal = std::max(extent.y, 1.0f);
    const float side = 0.25f * horizontal;
    // "A bit above the top": a tenth of the largest extent, so the light never touches the geometry.
    const float gap = 0.1f * std::max(horizontal, extent.y);
    // Offset sideways (towards +X and towards the default camera at +Z) so shadows fall visibly beside objects.
    const glm::vec3 lightCenter(center.x + 0.25f * extent.x, upper.y + gap, center.z + 0.15f * extent.z);

    AreaLight light;
    light.edgeU = glm::vec3(side, 0.0f, 0.0f);
    light.edgeV = glm::vec3(0.0f, 0.0f, side); // cross(+X, +Z) = -Y: faces down
    light.corner = lightCenter - 0.5f * (light.edgeU + light.edgeV);

    const glm::vec3 receiver(center.x, lower.y, center.z);
    const float geometry = lightGeometryFactor(light, receiver, glm::vec3(0.0f, 1.0f, 0.0f));
    light.radiance = glm::vec3(kTargetRadiance * glm::pi<float>() / geometry);
    return light;
}

} // namespace chcrt
