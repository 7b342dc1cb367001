// `chcrt info`: the OpenGL implementation, its limits and the scene's statistics; `chcrt methods`: the tracing
// methods of the registry (app/methods.h).
#include "app/commands.h"
#include "app/methods.h"
#include "app/report.h"
#include "app/session.h"
#include "renderer/core/error.h"
#include "renderer/gl/context.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/outofcore/gpu_cache_slots.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace chcrt::app {
namespace {

constexpr size_t kReportedFailures = 10; // subtree failures printed by --check (all are counted)

// Every subtree read back and checksummed; one message per subtree that fails (it names the file and subtree).
std::vector<std::string> checkSubtrees(const outofcore::ChsFile& file) {
    std::vector<std::string> failures;
    for (uint32_t i = 0; i < file.header().subtreeCount; ++i) {
        try {
            (void)file.readSubtree(i);
        } catch (const InputError& e) {
            failures.push_back(e.what());
        }
        for (uint32_t level = 1; level <= file.lodLevels(); ++level) { // its LOD proxies (issue #19)
            if (file.lodRecord(i, level).nodeCount == 0) continue;
            try {
                (void)file.readSubtree(i, level);
            } catch (const InputError& e) {
                failures.push_back(e.what());
            }
        }
    }
    return failures;
}

// --devices: every EGL device with what its driver says and the OpenGL renderer a context on it reports (or why
// none could be made). Each device gets a context of its own, made and destroyed here.
nlohmann::json listDevices(const CommonOptions& o) {
    const std::vector<EglDeviceInfo> devices = listEglDevices();
    std::printf("EGL devices: %zu%s\n", devices.size(),
                devices.empty() ? " (no EGL_EXT_device_enumeration, or no device: auto uses Mesa's surfaceless platform)" : "");
    nlohmann::json list = nlohmann::json::array();
    for (const EglDeviceInfo& d : devices) {
        std::string glRenderer, failure;
        bool glSoftware = false;
        try {
            const auto context = createHeadlessContext(GlBackend::Egl, false, d.index);
            const GlInfo gl = queryGlInfo();
            glRenderer = gl.renderer + " (OpenGL " + gl.version + ")";
            glSoftware = gl.softwareRenderer;
        } catch (const GlError& e) {
            failure = e.what();
        }
        const auto shown = [](const std::string& text) { return text.empty() ? std::string("-") : text; };
        std::printf("  device %d  %s  EGL renderer %s, vendor %s, DRM %s\n    OpenGL %s\n", d.index,
                    d.software || glSoftware ? "software" : "hardware", shown(d.renderer).c_str(), shown(d.vendor).c_str(),
                    shown(d.drmDevice).c_str(), failure.empty() ? glRenderer.c_str() : ("no 4.5 core context: " + failure).c_str());
        list.push_back({{"index", d.index}, {"software", d.software || glSoftware}, {"egl_software", d.software},
                        {"egl_renderer", d.renderer}, {"egl_vendor", d.vendor}, {"drm_device", d.drmDevice},
                        {"gl_renderer", glRenderer}, {"error", failure}});
    }
    std::printf("--gl-device %s picks:\n", o.glDevice == kAutoGlDevice ? "auto" : std::to_string(o.glDevice).c_str());
    return list;
}

} // namespace

int runInfo(const InfoOptions& options) {
    const CommonOptions& o = options.common;
    nlohmann::json devices;
    if (options.devices) devices = listDevices(o);
    const auto context = createHeadlessContext(o.gl, o.glDebug, o.glDevice);
    warnIfSoftwareRenderer(o, *context);
    const GlInfo info = queryGlInfo();
    const GpuMemoryInfo memory = queryGpuMemory();
    std::printf("OpenGL\n  context      %s\n  vendor       %s\n  renderer     %s%s\n  version      %s\n  GLSL         %s\n",
                context->description().c_str(), info.vendor.c_str(), info.renderer.c_str(),
                info.softwareRenderer ? " (software)" : "", info.version.c_str(), info.glslVersion.c_str());
    std::printf("  max texture buffer %d texels, max texture %d, draw buffers %d, KHR_debug %s\n",
                info.maxTextureBufferSize, info.maxTextureSize, info.maxDrawBuffers, info.khrDebug ? "yes" : "no");
    if (memory.reported) {
        std::printf("  GPU memory   %.0f MiB available of %s (%s)\n", double(memory.availableBytes) / double(1 << 20),
                    memory.totalBytes ? (std::to_string(memory.totalBytes >> 20) + " MiB").c_str() : "an unreported total",
                    memory.source.c_str());
    } else {
        std::printf("  GPU memory   not reported (no GL_NVX_gpu_memory_info or GL_ATI_meminfo)\n");
    }
    std::printf("  shader stage %s (--shader-stage %s), loop cap %s\n",
                toString(resolveTraceStage(o.shaderStage)), toString(o.shaderStage),
                currentRendererTraits().loopCap ? "compiled in (the renderer ends loops after 65,535 iterations)" : "off");
    nlohmann::json j = {{"gl", {{"context", context->description()}, {"vendor", info.vendor},
                                {"renderer", info.renderer}, {"version", info.version},
                                {"software_renderer", info.softwareRenderer},
                                {"shader_stage", toString(resolveTraceStage(o.shaderStage))},
                                {"loop_cap", currentRendererTraits().loopCap},
                                {"gpu_memory_reported", memory.reported},
                                {"gpu_memory_available_bytes", memory.availableBytes},
                                {"gpu_memory_total_bytes", memory.totalBytes},
                                {"max_texture_buffer_size", info.maxTextureBufferSize}}}};
    j.update(glJson(info));
    if (options.devices) {
        j["devices"] = devices;
        if (!o.statsJson.empty()) writeJsonFile(o.statsJson, j);
        return kExitOk;
    }
    if (!options.noScene && outofcore::isPreparedScenePath(o.scene)) {
        const outofcore::ChsFile file(o.scene);
        const outofcore::ChsHeader& h = file.header();
        const outofcore::ChsFileSummary f = outofcore::summarize(file);
        std::printf("Prepared scene %s (version %u, from %s)\n  triangles    %llu in %u subtrees (limits %u triangles, "
                    "height %u), %u parts\n  subtrees     triangles min %u / mean %.0f / max %u, nodes max %u, height max %u\n"
                    "  upper part   %u nodes\n  file         %.1f MB (subtrees %.1f MB, metadata %.2f MB)\n",
                    o.scene.c_str(), h.version, file.source().c_str(), (unsigned long long)h.triangleCount, h.subtreeCount,
                    h.subtreeTriangleLimit, h.subtreeHeightLimit, h.chunkCount, f.minTriangles, f.meanTriangles,
                    h.maxSubtreeTriangles, h.maxSubtreeNodes, f.maxHeight, h.upperNodeCount, double(h.fileBytes) / 1e6,
                    double(f.subtreeBytes) / 1e6, double(h.metaBytes) / 1e6);
        j["prepared"] = {{"file", o.scene}, {"source", file.source()}, {"triangles", h.triangleCount},
                         {"subtrees", h.subtreeCount}, {"upper_nodes", h.upperNodeCount}, {"parts", h.chunkCount},
                         {"file_bytes", h.fileBytes}, {"max_subtree_triangles", h.maxSubtreeTriangles},
                         {"max_subtree_nodes", h.maxSubtreeNodes}};
        { // The subtree layout and what a triangle costs in the file and in the GPU cache (issue #19, compact_subtree.h).
            uint64_t gpuBytes = 0;
            for (uint32_t i = 0; i < h.subtreeCount; ++i) {
                const outofcore::ChsSubtreeRecord& r = file.subtrees()[i];
                gpuBytes += outofcore::gpuEntryShape(r.nodeCount, r.triangleCount, file.vertexCount(i), file.compact()).bytes();
            }
            const double triangles = double(std::max<uint64_t>(h.triangleCount, 1));
            std::printf("  layout       %s: %.1f bytes per triangle in the file's subtrees, %.1f in the GPU cache\n",
                        file.compact() ? "compact (quantized nodes, indexed triangles)" : "full",
                        double(f.subtreeBytes) / triangles, double(gpuBytes) / triangles);
            j["prepared"]["layout"] = file.compact() ? "compact" : "full";
            j["prepared"]["subtree_bytes_per_triangle"] = double(f.subtreeBytes) / triangles;
            j["prepared"]["gpu_bytes_per_triangle"] = double(gpuBytes) / triangles;
        }
        if (file.lodLevels() > 0) { // LOD proxies (issue #19): what they cost against what they replace
            std::printf("  LOD proxies  %.1f MB = %.1f %% of the subtrees' bytes\n", double(f.proxyBytes) / 1e6,
                        f.subtreeBytes ? 100.0 * double(f.proxyBytes) / double(f.subtreeBytes) : 0.0);
            nlohmann::json levels = nlohmann::json::array();
            for (uint32_t level = 1; level <= file.lodLevels(); ++level) {
                std::vector<float> errors;
                for (uint32_t i = 0; i < h.subtreeCount; ++i) {
                    const outofcore::ChsLodRecord& r = file.lodRecord(i, level);
                    if (r.nodeCount != 0) errors.push_back(r.errorWorld);
                }
                std::sort(errors.begin(), errors.end());
                const float medianError = errors.empty() ? 0.0f : errors[errors.size() / 2];
                const uint64_t triangles = f.proxyTrianglesPerLevel[level - 1];
                std::printf("  level %u      %llu of %u subtrees, %llu triangles (%.2f %%), error median %.3g / max %.3g\n",
                            level, (unsigned long long)f.proxiesPerLevel[level - 1], h.subtreeCount,
                            (unsigned long long)triangles, 100.0 * double(triangles) / double(h.triangleCount),
                            double(medianError), errors.empty() ? 0.0 : double(errors.back()));
                levels.push_back({{"level", level}, {"proxies", f.proxiesPerLevel[level - 1]}, {"triangles", triangles},
                                  {"error_median", medianError}, {"error_max", errors.empty() ? 0.0f : errors.back()}});
            }
            j["prepared"]["lod"] = {{"levels", levels}, {"proxy_bytes", f.proxyBytes}, {"subtree_bytes", f.subtreeBytes}};
        }
        if (options.check) {
            const std::vector<std::string> bad = checkSubtrees(file);
            std::printf("  check        %u subtrees read: %s\n", h.subtreeCount,
                        bad.empty() ? "every checksum matches" : (std::to_string(bad.size()) + " failed").c_str());
            for (size_t i = 0; i < bad.size() && i < kReportedFailures; ++i) std::fprintf(stderr, "%s\n", bad[i].c_str());
            j["prepared"]["check_failures"] = bad.size();
            if (!o.statsJson.empty()) writeJsonFile(o.statsJson, j);
            if (!bad.empty()) return kExitCheckFailed;
        }
    } else if (options.check) {
        throw InputError("--check reads prepared scenes (.chs); " + (options.noScene ? std::string("--no-scene gives none") : o.scene + " is not one"));
    }
    if (!options.noScene && !outofcore::isPreparedScenePath(o.scene)) { // a .chs may not fit in core
        const SceneSession s = openSceneSession(o);
        const Aabb b = s.scene.bounds();
        std::printf("Scene %s\n  triangles    %llu (%llu unique; %u meshes, %u instances; %llu degenerate dropped)\n",
                    s.scene.name.c_str(), (unsigned long long)s.scene.triangleCount(),
                    (unsigned long long)s.scene.stats.uniqueTriangles, s.scene.stats.meshCount,
                    s.scene.stats.instanceCount, (unsigned long long)s.scene.stats.degenerateTrianglesDropped);
        std::printf("  vertices     %zu, materials %zu, textures %zu, cameras %zu\n", s.scene.positions.size(),
                    s.scene.materials.size(), s.scene.textures.size(), s.scene.cameras.size());
        std::printf("  bounds       (%.2f, %.2f, %.2f) - (%.2f, %.2f, %.2f), diagonal %.2f\n", b.lower.x, b.lower.y,
                    b.lower.z, b.upper.x, b.upper.y, b.upper.z, b.diagonal());
        std::printf("  loaded in    %.2f s\n", s.sceneSeconds);
        std::printf("BVH\n  build        %.2f s (%.2f Mtris/s)\n  nodes        %u (%u leaves, %.2f triangles/leaf)\n"
                    "  max depth    %u\n  SAH cost     %.2f\n  GPU bytes    %.1f MB\n",
                    s.bvh.stats.buildSeconds, double(s.scene.triangleCount()) / 1e6 / std::max(s.bvh.stats.buildSeconds, 1e-9),
                    s.bvh.stats.nodeCount, s.bvh.stats.leafCount, s.bvh.stats.averageLeafTriangles, s.bvh.stats.maxDepth,
                    s.bvh.stats.sahCost, double(s.bvh.stats.bytes) / 1e6);
        std::printf("Camera path %s: %d frames at %.0f fps\n", s.path.name.c_str(), s.path.frameCount(), s.path.fps);
        j["scene"] = toJson(s.scene);
        j["bvh"] = toJson(s.bvh.stats);
    }
    if (!o.statsJson.empty()) writeJsonFile(o.statsJson, j);
    return kExitOk;
}

int runMethods(const MethodsOptions& options) {
    const Table table = methodTable();
    std::fputs((options.markdown ? table.toMarkdown() : table.toText()).c_str(), stdout);
    return kExitOk;
}

} // namespace chcrt::app
