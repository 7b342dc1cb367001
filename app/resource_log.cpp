#include "app/resource_log.h"

#include "renderer/core/error.h"
#include "renderer/gl/gl.h"

#include <cerrno>
#include <cstring>
#include <utility>

namespace chcrt::app {

nlohmann::json resourcesJson(const ProcessResources& process, const GlObjectCounts& gl) {
    nlohmann::json objects = nlohmann::json::object();
    for (const auto& [name, count] : gl.named()) objects[name] = count;
    objects["total"] = gl.total();
    constexpr double kMiB = double(1u << 20);
    return {{"rss_mb", double(process.residentBytes) / kMiB},
            {"rss_anon_mb", double(process.residentAnonBytes) / kMiB},
            {"rss_file_mb", double(process.residentFileBytes) / kMiB},
            {"heap_in_use_mb", double(process.heapInUseBytes) / kMiB},
            {"open_files", process.openFiles},
            {"threads", process.threads},
            {"gl_objects", objects}};
}

nlohmann::json sampleResourcesJson() { return resourcesJson(sampleProcessResources(), liveGlObjects()); }

ResourceLog::ResourceLog(const std::string& file, int every) : file_(file), every_(every) {
    if (every < 1) throw InputError("--resource-every must be at least 1");
    out_ = std::fopen(file.c_str(), "w");
    if (!out_) throw InputError(file + ": cannot create the resource log: " + std::strerror(errno));
}

ResourceLog::~ResourceLog() {
    if (out_) std::fclose(out_);
}

ResourceLog::ResourceLog(ResourceLog&& o) noexcept
    : file_(std::move(o.file_)), out_(std::exchange(o.out_, nullptr)), every_(o.every_), lastWritten_(o.lastWritten_) {}

ResourceLog& ResourceLog::operator=(ResourceLog&& o) noexcept {
    if (this != &o) {
        if (out_) std::fclose(out_);
        file_ = std::move(o.file_);
        out_ = std::exchange(o.out_, nullptr);
        every_ = o.every_;
        lastWritten_ = o.lastWritten_;
    }
    return *this;
}

void ResourceLog::frameDone(uint64_t frame, bool last, const nlohmann::json& extra) {
    if (!out_ || (!last && frame % uint64_t(every_) != 0) || int64_t(frame) == lastWritten_) return;
    lastWritten_ = int64_t(frame);
    // The sample counts what the process holds once the GL work queued so far is done (the driver frees what a
    // deleted object's last draw still used when that draw completes), not the free pages the allocator kept since
    // its last release.
    glFinish();
    releaseFreedMemory();
    nlohmann::json line = sampleResourcesJson();
    line["frame"] = frame;
    for (const auto& [key, value] : extra.items()) line[key] = value;
    const std::string text = line.dump() + "\n";
    if (std::fwrite(text.data(), 1, text.size(), out_) != text.size() || std::fflush(out_) != 0) {
        throw InputError(file_ + ": writing the resource log failed: " + std::strerror(errno));
    }
}

} // namespace chcrt::app
