#include "renderer/reference/embree_tracer.h"

#include "renderer/core/error.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace chcrt {

struct EmbreeTracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;

    // Embree reports errors through a C callback, which must not throw; the first message is kept here and
    // rethrown by the calling C++ code after the Embree call returns.
    mutable std::mutex errorMutex;
    mutable std::string firstError;

    static void onError(void* user, RTCError code, const char* message) {
        auto* impl = static_cast<Impl*>(user);
        std::lock_guard lock(impl->errorMutex);
        if (impl->firstError.empty()) {
            impl->firstError = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
        }
    }

    void throwIfError(const char* during) const {
        std::lock_guard lock(errorMutex);
        if (!firstError.empty()) {
            std::string message = firstError + " (during " + during + ")";
            firstError.clear();
            throw std::runtime_error(message);
        }
    }

    ~Impl() {
        if (scene) {
            rtcReleaseScene(scene);
        }
        if (device) {
            rtcReleaseDevice(device);
        }
    }
};

namespace {

// Ray windows. Our tracers accept hits with tmin <= t <= tmax. Embree 3.13's robust (Pluecker) triangle test,
// which RTC_SCENE_FLAG_ROBUST selects, accepts tnear <= t <= tfar: the same window, so tmin/tmax map directly
// onto tnear/tfar. (The default Moeller-Trumbore path is strict at the near end, tnear < t: a hit at exactly
// t == tmin would be lost.) Embree's t itself may differ from ours in the last bits (it divides through a
// reciprocal whose precision depends on the CPU's instruction set), so hits within an ulp or two of a window end
// can differ between Embree and the GLSL tracers; tests/core/embree_tracer_test.cpp WindowIsInclusiveAtBothEnds
// checks the window a few ulps inside and outside each end. Embree requires tnear >= 0, so a
// negative tmin is clamped to 0: only hits behind the ray origin are lost, which no caller asks for.
// Rays with tmax <= tmin are never handed to Embree: with its inclusive test, tmax == tmin would still accept a
// hit at exactly that t, while such rays are inactive for us.
float embreeTnear(float tmin) {
    return std::max(tmin, 0.0f);
}

bool isActive(const Ray& ray) {
    return ray.tmax > ray.tmin;
}

void traceClosest(RTCScene scene, const Ray& ray, Hit& hit) {
    hit = Hit{};
    if (!isActive(ray)) {
        return;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit query{};
    query.ray.org_x = ray.origin.x;
    query.ray.org_y = ray.origin.y;
    query.ray.org_z = ray.origin.z;
    query.ray.tnear = embreeTnear(ray.tmin);
    query.ray.dir_x = ray.direction.x;
    query.ray.dir_y = ray.direction.y;
    query.ray.dir_z = ray.direction.z;
    query.ray.time = 0.0f;
    query.ray.tfar = ray.tmax;
    query.ray.mask = 0xFFFFFFFFu;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &query);
    if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        // Embree's (u, v) weight v1 and v2, the same convention as intersectRayTriangle.
        hit.t = query.ray.tfar;
        hit.triangleId = query.hit.primID;
        hit.u = query.hit.u;
        hit.v = query.hit.v;
    }
}

// rtcOccluded only says whether something is in [tmin, tmax], not where or what: an occluded ray reports
// triangleId = 0 and t = 0, so callers must use hit() and nothing else of any-hit results.
void traceAny(RTCScene scene, const Ray& ray, Hit& hit) {
    hit = Hit{};
    if (!isActive(ray)) {
        return;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay query{};
    query.org_x = ray.origin.x;
    query.org_y = ray.origin.y;
    query.org_z = ray.origin.z;
    query.tnear = embreeTnear(ray.tmin);
    query.dir_x = ray.direction.x;
    query.dir_y = ray.direction.y;
    query.dir_z = ray.direction.z;
    query.time = 0.0f;
    query.tfar = ray.tmax;
    query.mask = 0xFFFFFFFFu;
    rtcOccluded1(scene, &context, &query);
    if (query.tfar == -std::numeric_limits<float>::infinity()) { // Embree's "occluded" marker
        hit.triangleId = 0;
        hit.t = 0.0f;
    }
}

} // namespace

EmbreeTracer::EmbreeTracer(const Scene& scene) : impl_(std::make_unique<Impl>()) {
    for (const glm::uvec3& triangle : scene.triangles) {
        if (std::max({triangle.x, triangle.y, triangle.z}) >= scene.positions.size()) {
            throw InputError("EmbreeTracer: scene \"" + scene.name + "\" has a vertex index out of range");
        }
    }
    const auto start = std::chrono::steady_clock::now();
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device) {
        throw std::runtime_error("Embree error " + std::to_string(int(rtcGetDeviceError(nullptr))) +
                                 ": cannot create a device");
    }
    rtcSetDeviceErrorFunction(impl_->device, &Impl::onError, impl_.get());

    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    // Robust mode: watertight edge tests, so a ray through a shared edge hits one of the two triangles.
    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    if (!scene.triangles.empty()) {
        RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
        // Copied into Embree-owned buffers: those carry the tail padding Embree's SIMD vertex loads need, which
        // a shared std::vector<glm::vec3> does not.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), scene.positions.size()));
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), scene.triangles.size()));
        try {
            impl_->throwIfError("buffer allocation");
        } catch (...) {
            rtcReleaseGeometry(geometry); // it holds a reference to the device
            throw;
        }
        for (size_t i = 0; i < scene.positions.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
                vertices[i * 3 + size_t(k)] = scene.positions[i][k];
            }
        }
        for (size_t i = 0; i < scene.triangles.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
                indices[i * 3 + size_t(k)] = scene.triangles[i][k];
            }
        }
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(impl_->scene, geometry); // geomID 0; primID = index into scene.triangles
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(impl_->scene);
    impl_->throwIfError("scene build");
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeTracer::~EmbreeTracer() = default;

void EmbreeTracer::trace(std::span<const Ray> rays, std::span<Hit> hits, bool anyHit) const {
    if (rays.size() != hits.size()) {
        throw std::invalid_argument("EmbreeTracer::trace: " + std::to_string(rays.size()) + " rays but " +
                                    std::to_string(hits.size()) + " hits");
    }
    RTCScene scene = impl_->scene;
    // One rtcIntersect1/rtcOccluded1 per ray. 16-wide packets (rtcIntersect16, AVX-512 here) were measured at
    // the same speed within 2% on 1M random rays against a 1M-triangle soup (tests/core/embree_bench.cpp): random
    // rays are memory-bound and incoherent, so packets buy nothing and cost the SoA shuffling.
    // Chunks are handed out dynamically: incoherent rays take very different times, static halves would idle.
    constexpr size_t kChunk = 1024;
    std::atomic<size_t> next{0};
    const auto work = [&] {
        for (size_t begin = next.fetch_add(kChunk); begin < rays.size(); begin = next.fetch_add(kChunk)) {
            const size_t end = std::min(rays.size(), begin + kChunk);
            for (size_t i = begin; i < end; ++i) {
                if (anyHit) {
                    traceAny(scene, rays[i], hits[i]);
                } else {
                    traceClosest(scene, rays[i], hits[i]);
                }
            }
        }
    };
    const size_t threadCount =
        std::min<size_t>(std::max(1u, std::thread::hardware_concurrency()), (rays.size() + kChunk - 1) / kChunk);
    std::vector<std::thread> helpers;
    for (size_t t = 1; t < threadCount; ++t) {
        helpers.emplace_back(work);
    }
    work();
    for (std::thread& helper : helpers) {
        helper.join();
    }
    impl_->throwIfError("tracing");
}

} // namespace chcrt
