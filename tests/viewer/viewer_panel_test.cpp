// The viewer's panel (app/viewer/viewer_ui.h) drawn by Dear ImGui without a window or GL: ImGui lays out and logs
// its text on the CPU, so the panel's size, what its text says and where its items end can be checked. A 1280×720
// display is the viewer's default window.
#include "app/viewer/viewer_ui.h"

#include <imgui.h>
#include <imgui_internal.h>

#include <gtest/gtest.h>

#include <string>

namespace chcrt::app {
namespace {

class HeadlessImGui {
public:
    HeadlessImGui(float width, float height) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(width, height);
        io.DeltaTime = 1.0f / 30.0f;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsAlpha8(&pixels, &w, &h); // builds the font atlas, as a backend would
        // ImGui's text log ends with the first window that ends, handing the text to the clipboard: here.
        io.ClipboardUserData = &clipboard_;
        io.SetClipboardTextFn = [](void* user, const char* text) { *static_cast<std::string*>(user) = text; };
        ImGui::StyleColorsDark();
    }
    ~HeadlessImGui() { ImGui::DestroyContext(); }
    HeadlessImGui(const HeadlessImGui&) = delete;
    HeadlessImGui& operator=(const HeadlessImGui&) = delete;

    // Draws `frames` frames of the panel (ImGui sizes windows from the previous frame's content); returns the text
    // the last one drew, line by line.
    std::string draw(ViewerPanel& panel, ViewerSettings& settings, const ViewerStatus& status, int frames = 4) {
        clipboard_.clear();
        for (int i = 0; i < frames; ++i) {
            ImGui::NewFrame();
            if (i + 1 == frames) ImGui::LogToClipboard(0); // 0: closed sections stay closed
            panel.draw(settings, status);
            ImGui::Render();
        }
        return clipboard_;
    }
    static ImGuiWindow* panelWindow() { return ImGui::FindWindowByName("chcrt view"); }

private:
    std::string clipboard_;
};

// A status as after a rendered frame of a CHC+RT method out of core: every section of the panel has content.
ViewerStatus busyStatus() {
    ViewerStatus s;
    s.frameRendered = true;
    s.frameMs = 180.5;
    s.internalWidth = 640;
    s.internalHeight = 360;
    s.stats.totalMs = 170.25;
    s.stats.gbufferMs = 20.5;
    s.stats.raygenMs = 1.5;
    s.stats.trace[size_t(RayType::Primary)] = {36, 90.0};
    s.stats.trace[size_t(RayType::Shadow)] = {72, 60.0};
    s.stats.raysGenerated = 460800;
    for (int i = 0; i < 120; ++i) s.frameHistoryMs.push_back(150.0f + float(i % 7) * 10.0f);
    ViewerChcrtStats c;
    c.traces = 2, c.queries = 123456, c.subtreesScheduled = 34567, c.shaderCalls = 4567, c.queriesSkippedExtent = 98765;
    c.phase1Ms = 30, c.phase2Ms = 20, c.phase3Ms = 70;
    s.chcrt = c;
    ViewerOutOfCoreStatus o;
    o.frame.cacheHits = 1234, o.frame.cacheMisses = 56, o.frame.cachePostponed = 7, o.frame.queries = 123456;
    o.frame.traceMs = 150, o.frame.raysTraced = 460800, o.frame.slots = 220, o.frame.residentSubtrees = 219;
    o.gpuCacheMb = 1024, o.hostCacheMb = 2048, o.fileSubtrees = 3221;
    s.outOfCore = o;
    s.sceneName = "city140m_prepared_with_65536_triangle_subtrees.chs";
    s.triangles = 140000000;
    s.pathFrames = 300;
    s.message = "frame not rendered: /data/scenes/city140m.chs: reading subtree 1234: Input/output error";
    s.frameError = "/data/scenes/city140m.chs: reading subtree 1234: Input/output error";
    return s;
}

TEST(ViewerPanel, FitsA720PixelWindowAndClipsNoText) {
    HeadlessImGui imgui(1280, 720);
    ViewerPanel panel("city140m.chs");
    ViewerSettings settings;
    settings.method = "chcrt";
    const ViewerStatus status = busyStatus();
    imgui.draw(panel, settings, status);
    const ImGuiWindow* window = HeadlessImGui::panelWindow();
    ASSERT_NE(window, nullptr);
    // Inside the window: the panel scrolls instead of running off its bottom edge.
    EXPECT_GE(window->Pos.y, 0.0f);
    EXPECT_LE(window->Pos.y + window->Size.y, 720.0f) << "panel from y " << window->Pos.y << ", height " << window->Size.y;
    EXPECT_GT(window->ContentSize.y, window->Size.y) << "all sections open: more than fits, so it scrolls";
    EXPECT_TRUE(window->ScrollbarY);
    // No item reaches past the panel's right edge, where ImGui clips it.
    EXPECT_LE(window->ContentSizeIdeal.x, window->WorkRect.GetWidth() + 1.0f)
        << "widest item " << window->ContentSizeIdeal.x << " px, room for " << window->WorkRect.GetWidth() << " px";
}

TEST(ViewerPanel, TheFrameTimeGraphIsAGraph) {
    HeadlessImGui imgui(1280, 720);
    ViewerPanel panel("city");
    ViewerSettings settings;
    imgui.draw(panel, settings, busyStatus());
    const ImGuiWindow* window = HeadlessImGui::panelWindow();
    ASSERT_NE(window, nullptr);
    const auto [width, height] = panel.graphSize();
    EXPECT_GE(width, 0.9f * window->WorkRect.GetWidth()) << "graph " << width << " x " << height;
    EXPECT_GE(height, 40.0f);
}

TEST(ViewerPanel, BeforeTheFirstFrameItShowsTheLoadAndNoFrameStatistics) {
    HeadlessImGui imgui(1280, 720);
    ViewerPanel panel("city");
    ViewerSettings settings;
    ViewerStatus loading; // the first scene is loading: nothing rendered yet
    loading.loading = true;
    loading.loadingScene = "city";
    loading.loadingSeconds = 1.25;
    loading.loadingStep = "Building BVH";
    loading.loadingStepNumber = 2;
    loading.loadingFraction = 0.4;
    loading.frameMs = 3.65; // what a loop iteration that renders nothing takes
    const std::string text = imgui.draw(panel, settings, loading);
    EXPECT_NE(text.find("Loading city"), std::string::npos) << text;
    EXPECT_NE(text.find("Building BVH"), std::string::npos) << text;
    EXPECT_NE(text.find("no frame rendered yet"), std::string::npos) << text;
    for (const char* absent : {"fps", "internal 0 x 0", "0.00 ms", "Mrays/s"}) {
        EXPECT_EQ(text.find(absent), std::string::npos) << absent << " in:\n" << text;
    }
    const std::string rendered = imgui.draw(panel, settings, busyStatus());
    EXPECT_NE(rendered.find("5.5 fps"), std::string::npos) << rendered; // 1000 / 180.5 ms
    EXPECT_NE(rendered.find("internal 640 x 360"), std::string::npos) << rendered;
}

TEST(ViewerPanel, AFailedFrameIsShownWithItsError) {
    HeadlessImGui imgui(1280, 720);
    ViewerPanel panel("c.chs");
    ViewerSettings settings;
    const std::string text = imgui.draw(panel, settings, busyStatus());
    EXPECT_NE(text.find("frame not rendered"), std::string::npos) << text;
    EXPECT_NE(text.find("reading subtree 1234: Input/output error"), std::string::npos) << text;
}

} // namespace
} // namespace chcrt::app
