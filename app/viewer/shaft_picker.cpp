#include "app/viewer/shaft_picker.h"

#include "renderer/core/error.h"

#include <cstdio>

namespace chcrt::app {

void ShaftPicker::update(const Bvh& bvh, bool sceneInCore, const Camera& camera, int w, int h,
                         const ls::LineSpaceParams& params) {
    if (!sceneInCore) { // the node's Line Space is built from the in-core BVH
        pick_.reset();
        info_ = {"the shafts view needs the scene in core (out of core only subtrees are on the GPU)"};
        notice_(info_.back(), true);
        return;
    }
    const std::string parameters =
        std::to_string(params.n) + "/" + std::to_string(params.depth) + "/" + std::to_string(params.triangleThreshold);
    if (job_.busy()) {
        if (!job_.finished() && !scripted_) return; // the previous pick stays shown meanwhile
        finish(); // scripts wait for it in place
    }
    if (!pending_ && !pick_ && parameters_.empty()) pending_ = std::make_pair(w / 2, h / 2);
    if (pending_) {
        camera_ = camera;
        width_ = w;
        height_ = h;
        pixel_ = *pending_;
    } else if (parameters == parameters_) {
        return;
    }
    pending_.reset();
    parameters_ = parameters;
    result_ = std::make_shared<std::optional<ShaftPick>>();
    job_.start("Line Space of the picked node",
               [result = result_, &bvh, camera = camera_, w = width_, h = height_, pixel = pixel_, n = params.n,
                depth = params.depth, t = params.triangleThreshold](Progress& progress) {
                   progress.begin("Line Space of the picked node", 0);
                   *result = pickLineSpaceNode(bvh, camera, w, h, pixel.first, pixel.second, n, depth, t);
                   progress.end();
               });
    info_ = {"pixel " + std::to_string(pixel_.first) + ", " + std::to_string(pixel_.second) +
             ": building the Line Space of its node ..."};
    if (scripted_) finish();
}

bool ShaftPicker::takeFinished() {
    if (!job_.busy() || !job_.finished()) return false;
    finish();
    return true;
}

void ShaftPicker::sceneChanged() {
    discardJob(job_);
    pick_.reset(); // a node of the previous scene: the new one starts with the centre pixel
    parameters_.clear();
}

// Takes the finished job's node and describes it in the panel.
void ShaftPicker::finish() {
    try {
        job_.take();
    } catch (const InputError& error) {
        pick_.reset();
        info_ = {std::string("shafts: ") + error.what()};
        notice_(info_.back(), false);
        return;
    }
    pick_ = std::move(*result_);
    info_.clear();
    if (!pick_) {
        info_.push_back("pixel " + std::to_string(pixel_.first) + ", " + std::to_string(pixel_.second) +
                        ": no hit (click on geometry)");
        notice_(info_.back(), false);
        return;
    }
    const ShaftPick& p = *pick_;
    char line[200];
    std::snprintf(line, sizeof(line), "node %u of %u (BVH node %u, %u triangles), N=%u D=%u T=%u", p.space,
                  p.spaceCount, p.bvhNode, p.subtreeTriangles, p.n, p.depth, p.triangleThreshold);
    info_.push_back(line);
    std::snprintf(line, sizeof(line), "%llu shafts, %llu filled: fill rate %.1f %%", (unsigned long long)p.shafts,
                  (unsigned long long)p.filled, 100.0 * p.fillRate());
    info_.push_back(line);
    std::snprintf(line, sizeof(line), "picked pixel %d, %d (triangle %u); built in %.0f ms (worker thread)", p.pixelX,
                  p.pixelY, p.triangleId, p.buildMs);
    info_.push_back(line);
    std::snprintf(line, sizeof(line), "shafts: node %u, %llu shafts, fill rate %.1f %%", p.space,
                  (unsigned long long)p.shafts, 100.0 * p.fillRate());
    notice_(line, false);
}

} // namespace chcrt::app
