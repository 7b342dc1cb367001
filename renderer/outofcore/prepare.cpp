#include "renderer/outofcore/prepare.h"

#include "renderer/core/error.h"
#include "renderer/outofcore/chs_writer.h"
#include "renderer/scene/procedural/procedural.h"
#include "renderer/scene/procedural/procedural_internal.h"
#include "renderer/scene/scene_loader.h"

#include <chrono>

namespace chcrt::outofcore {
namespace {

std::string mb(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB"; }

// Parts of the city: the ground first, then runs of consecutive buildings of at most `budget` triangles.
struct CityPart { bool ground; uint32_t begin, end; uint64_t triangles; };

std::vector<CityPart> planCityParts(const procedural::CityParts& city, uint64_t budget, uint64_t memoryBytes) {
    auto tooSmall = [&](uint64_t triangles) {
        return InputError("--memory-mb " + std::to_string(memoryBytes >> 20) + " is too small: a part of " +
                          std::to_string(triangles) + " triangles needs about " +
                          mb(triangles * kPrepareBytesPerTriangle));
    };
    if (city.groundTriangles() > budget) throw tooSmall(city.groundTriangles());
    std::vector<CityPart> parts{{true, 0, 0, city.groundTriangles()}};
    CityPart current{false, 0, 0, 0};
    for (uint32_t b = 0; b < city.buildingCount(); ++b) {
        const uint64_t t = city.buildingTriangles(b);
        if (t > budget) throw tooSmall(t);
        if (current.triangles + t > budget) {
            parts.push_back(current);
            current = {false, b, b, 0};
        }
        current.end = b + 1;
        current.triangles += t;
    }
    if (current.end > current.begin) parts.push_back(current);
    return parts;
}

ChsSceneInfo infoFor(const std::string& source, const Scene& scene, const AreaLight& light) {
    ChsSceneInfo info;
    info.source = source;
    info.materials = scene.materials;
    info.light = light;
    if (!scene.cameras.empty()) {
        info.hasCamera = true;
        info.camera = scene.cameras.front().camera;
    }
    return info;
}

} // namespace

void parseGrid(const std::string& text, uint32_t& x, uint32_t& z) {
    const size_t sep = text.find('x');
    auto number = [&](const std::string& s) {
        if (s.empty() || s.size() > 4 || s.find_first_not_of("0123456789") != std::string::npos || std::stoul(s) == 0)
            throw InputError("grid '" + text + "': expected NxM with whole numbers from 1 to 9999");
        return uint32_t(std::stoul(s));
    };
    if (sep == std::string::npos) throw InputError("grid '" + text + "': expected NxM, e.g. 4x4");
    x = number(text.substr(0, sep));
    z = number(text.substr(sep + 1));
}

PrepareReport prepareScene(const std::string& sceneArg, const std::filesystem::path& output,
                           const PrepareOptions& options, Progress& progress) {
    const auto start = std::chrono::steady_clock::now();
    std::string scene = sceneArg;
    uint32_t gridX = options.gridX, gridZ = options.gridZ;
    if (scene.rfind("grid:", 0) == 0) { // grid:NxM:<scene>
        const size_t sep = scene.find(':', 5);
        if (sep == std::string::npos) throw InputError("--scene " + sceneArg + ": expected grid:NxM:<scene>");
        parseGrid(scene.substr(5, sep - 5), gridX, gridZ);
        scene = scene.substr(sep + 1);
    }
    const uint64_t copies = uint64_t(gridX) * gridZ;
    const uint64_t budgetTriangles = options.memoryBytes / kPrepareBytesPerTriangle;
    ChsWriter writer(output, {options.subtreeTriangles, options.subtreeHeight, options.lodLevels, options.compact});
    PrepareReport report;
    ProceduralSpec spec;
    const bool procedural = parseProceduralSpec(scene, spec);
    const std::string source = copies > 1 ? "grid:" + std::to_string(gridX) + "x" + std::to_string(gridZ) + ":" +
                                                (procedural ? toString(spec) : scene)
                                          : (procedural ? toString(spec) : scene);
    if (procedural && spec.kind == ProceduralKind::City && copies == 1 && spec.targetTriangles > budgetTriangles) {
        // Streaming: parts of the city, each generated, built and written, then dropped.
        const procedural::CityParts city(spec);
        const std::vector<CityPart> parts = planCityParts(city, budgetTriangles, options.memoryBytes);
        uint64_t total = 0, done = 0;
        for (const CityPart& p : parts) total += p.triangles;
        progress.begin("Preparing " + toString(spec) + " in " + std::to_string(parts.size()) + " parts", total);
        std::vector<Material> materials;
        for (const CityPart& p : parts) {
            Scene part;
            procedural::MeshBuilder builder(part);
            builder.reserve(p.triangles + 16, 2 * p.triangles + 64);
            city.generate(p.ground, p.begin, p.end, builder);
            if (materials.empty()) materials = part.materials;
            const Bvh bvh = buildBvh(part, options.bvh);
            writer.addChunk(part, bvh, writer.triangleCount());
            done += p.triangles;
            progress.update(done);
        }
        progress.end();
        Scene materialScene;
        materialScene.materials = materials;
        report.chunks = uint32_t(parts.size());
        report.fileBytes = writer.finish(infoFor(source, materialScene, proceduralAreaLight(spec)));
    } else {
        // In core once: the scene (and its BVH) must fit the budget; copies are written from the one BVH.
        Scene s;
        AreaLight light;
        if (procedural) {
            const bool analytic = spec.kind != ProceduralKind::City && spec.kind != ProceduralKind::Interior &&
                                  spec.kind != ProceduralKind::Plant; // tiny; their count is not a target
            if (!analytic && spec.targetTriangles > budgetTriangles) {
                throw InputError("--memory-mb " + std::to_string(options.memoryBytes >> 20) + " is too small for " +
                                 toString(spec) + " (needs about " + mb(spec.targetTriangles * kPrepareBytesPerTriangle) +
                                 "; only cities are prepared in parts)");
            }
            progress.begin("Generating " + toString(spec), 0);
            s = generateProceduralScene(spec);
            progress.end();
            light = proceduralAreaLight(spec);
        } else {
            s = loadSceneFile(scene, progress);
            light = defaultAreaLight(s);
            if (s.triangleCount() > budgetTriangles) {
                throw InputError("--memory-mb " + std::to_string(options.memoryBytes >> 20) + " is too small for " +
                                 scene + " (" + std::to_string(s.triangleCount()) + " triangles need about " +
                                 mb(s.triangleCount() * kPrepareBytesPerTriangle) + ")");
            }
        }
        validateScene(s);
        const Bvh bvh = buildBvh(s, options.bvh, progress);
        const Aabb b = s.bounds();
        const glm::vec3 pitch = 1.1f * b.extent();
        progress.begin("Writing " + std::to_string(copies) + (copies == 1 ? " copy" : " copies"), copies);
        for (uint32_t z = 0; z < gridZ; ++z) {
            for (uint32_t x = 0; x < gridX; ++x) {
                const glm::vec3 offset(float(x) * pitch.x, 0.0f, float(z) * pitch.z);
                writer.addChunk(s, bvh, writer.triangleCount(), offset);
                progress.update(uint64_t(z) * gridX + x + 1);
            }
        }
        progress.end();
        if (copies > 1) { // the light covers the whole grid: the scene's light moved to the grid's centre
            const glm::vec3 centre(0.5f * float(gridX - 1) * pitch.x, 0.0f, 0.5f * float(gridZ - 1) * pitch.z);
            light.corner += centre;
        }
        report.chunks = uint32_t(copies);
        report.fileBytes = writer.finish(infoFor(source, s, light));
    }
    report.triangles = writer.triangleCount();
    report.subtrees = writer.subtreeCount();
    report.subtreeBytes = writer.subtreeBytes();
    report.proxyBytes = writer.proxyBytes();
    report.proxies = writer.proxyCount();
    report.vertices = writer.vertexCount();
    report.compact = options.compact;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace chcrt::outofcore
