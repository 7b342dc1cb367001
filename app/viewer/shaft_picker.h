#pragma once
// The shafts view's pick (shaft_view.h): the picked pixel, the Line Space node under it, built on a worker (a node
// of a big scene at a low cut depth holds many triangles; the previous pick stays shown meanwhile, scripts wait),
// and the panel's lines about it. A new pick is taken at the current camera; a change of N/D/T recomputes the node
// of the same pixel of the camera it was picked with; without any pick the centre pixel is picked.
#include "app/viewer/background_job.h"
#include "app/viewer/shaft_view.h"
#include "linespace/linespace_build.h"
#include "renderer/bvh/bvh.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace chcrt::app {

class ShaftPicker {
public:
    // `notice(text, onlyIfNew)`: a message for the panel (and a scripted session's output).
    using Notice = std::function<void(const std::string& text, bool onlyIfNew)>;
    ShaftPicker(Notice notice, bool scripted) : notice_(std::move(notice)), scripted_(scripted) {}

    void requestPick(int x, int y) { pending_ = std::make_pair(x, y); } // internal image, rows top to bottom
    // Called when the shafts view renders a w × h frame at `camera`; `params`: N, D, T of the Line Spaces shown.
    void update(const Bvh& bvh, bool sceneInCore, const Camera& camera, int w, int h, const ls::LineSpaceParams& params);
    // The worker has finished a node: true after taking it (the view must render again).
    bool takeFinished();
    // A new scene: waits for the worker (it reads the previous BVH) and forgets the pick.
    void sceneChanged();
    bool busy() const { return job_.busy(); }

    const std::optional<ShaftPick>& pick() const { return pick_; }
    const std::vector<std::string>& info() const { return info_; } // a line each, for the panel

private:
    void finish();

    Notice notice_;
    bool scripted_ = false;
    std::optional<std::pair<int, int>> pending_;
    std::optional<ShaftPick> pick_;
    Camera camera_;
    int width_ = 0, height_ = 0;
    std::pair<int, int> pixel_{0, 0};
    std::string parameters_; // N/D/T the pick was computed with; empty before the first
    std::vector<std::string> info_;
    std::shared_ptr<std::optional<ShaftPick>> result_;
    BackgroundJob job_; // last: destroyed (joined) first
};

} // namespace chcrt::app
