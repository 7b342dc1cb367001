#pragma once
// The viewer's tracing method: the tracer made for the settings' method and parameters, switched live. A switch
// to a method with Line Spaces or an N-tree first builds them on a worker into the disk cache (the current
// tracer keeps rendering meanwhile; scripts wait), then makes the tracer, which loads them. Out of core, methods
// without an out-of-core form are refused and the previous one stays. It owns the tracer, the first tracer a
// loading worker made for a new scene, the cache build job and, with `--ls-cache ""`, a private cache directory.
#include "app/session.h"
#include "app/viewer/background_job.h"
#include "app/viewer/viewer_settings.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/render/renderer.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace chcrt::app {

// `--ls-cache ""` (no cache) in the viewer: a method switch's Line Space / N-tree build still goes through a cache
// directory, so that it runs on the worker (methodCacheBuild) while the window keeps drawing (issue #6), but a
// private temporary one, removed when the viewer exits: nothing outlives the session, as the flag asks.
class PrivateCacheDirectory {
public:
    PrivateCacheDirectory() = default;
    PrivateCacheDirectory(const PrivateCacheDirectory&) = delete;
    PrivateCacheDirectory& operator=(const PrivateCacheDirectory&) = delete;
    ~PrivateCacheDirectory();
    void create(); // a new directory chcrt-view-<pid>-<n> in the temporary directory
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

class MethodSwitcher {
public:
    using Notice = std::function<void(const std::string&)>;
    MethodSwitcher(Notice notice, bool scripted) : notice_(std::move(notice)), scripted_(scripted) {}

    // Method, always-cull and parameters a tracer is made for.
    static std::string tracerKey(const ViewerSettings& settings);
    // Whether the settings ask for another tracer than the active one.
    bool changed(const ViewerSettings& settings) const;
    // Makes the settings' tracer (or keeps the active one while its Line Spaces build, or refuses the method, with a
    // notice, correcting `settings.method`) and installs it in the renderer. `scene.options` gets the settings'
    // method parameters (methods read them from there).
    void apply(ViewerSettings& settings, SceneSession& scene, Renderer& renderer);

    // A new scene: waits for the build of the previous one and frees the tracer (before the renderer goes).
    void sceneChanged();
    // The next apply's tracer when it is made for `key` (tracerKey), made by the loading worker.
    void offerPremade(std::unique_ptr<Tracer> tracer, std::string key);
    void dropPremade() { premade_.reset(); }
    void releaseTracer(); // with its GL context current

    // With `--ls-cache ""` the session's private cache directory (its path, for the options of loads).
    const std::filesystem::path& usePrivateCache();

    Tracer* tracer() const { return tracer_.get(); }
    // The tracer when it traces out of core (--out-of-core with a prepared scene, CHC+RT §5.4), else nullptr.
    outofcore::OutOfCoreTracer* outOfCore() const { return outOfCore_; }
    ChcrtTracer* chcrt() const; // CHC+RT statistics and debug images, in core or out of core
    const std::string& activeMethod() const { return activeMethod_; }
    bool activeAlwaysCull() const { return activeAlwaysCull_; }
    // A method switch's Line Space / N-tree build on a worker.
    const BackgroundJob& cacheJob() const { return cacheJob_; }

private:
    bool prepareCache(const ViewerSettings& settings, const SceneSession& scene);
    std::unique_ptr<Tracer> create(const std::string& method, const ViewerSettings& settings, const SceneSession& scene);
    void createWithFallback(ViewerSettings& settings, SceneSession& scene, const std::string& previous);

    Notice notice_;
    bool scripted_ = false;
    std::unique_ptr<Tracer> tracer_;
    std::unique_ptr<Tracer> premade_;
    std::string premadeKey_;
    outofcore::OutOfCoreTracer* outOfCore_ = nullptr;
    std::string activeMethod_;
    bool activeAlwaysCull_ = false;
    std::string activeParameters_;
    // Removed after cacheJob_ has ended (declared first).
    PrivateCacheDirectory privateCache_;
    BackgroundJob cacheJob_;
    std::string cacheWarmKey_; // method + parameters whose build is in the disk cache (or needs none)
};

} // namespace chcrt::app
