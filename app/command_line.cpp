// What build/bin/chcrt and build/bin/chcrt-view share on the command line: error reporting (errors from the
// library are caught once and become a one-line message and an exit code; app/commands.h, docs/cli.md), parsing,
// and the flags of `chcrt view`.
#include "app/commands.h"

#include "app/methods.h"
#include "app/viewer/view_modes.h"
#include "renderer/core/error.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <vector>

namespace chcrt::app {

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        if (item.empty()) continue;
        // A name twice is a slip (bench would measure a method twice), never a request.
        if (std::find(items.begin(), items.end(), item) != items.end()) {
            throw InputError("'" + item + "' is listed twice in '" + text + "'");
        }
        items.push_back(item);
    }
    if (items.empty()) throw InputError("empty list '" + text + "'");
    return items;
}

int runReportingErrors(const std::function<int()>& body) {
    try {
        return body();
    } catch (const InputError& e) {
        std::fprintf(stderr, "chcrt: error: %s\n", e.what());
        return kExitBadInput;
    } catch (const GlError& e) {
        std::fprintf(stderr, "chcrt: OpenGL error: %s\n", e.what());
        return kExitGl;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "chcrt: internal error: %s\n", e.what());
        return kExitInternal;
    }
}

namespace {

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// "unknown command 'rendr' (did you mean 'render'? ...)" when the words before the first flag name no command of
// the (sub)command they follow; empty when they do. CLI11 itself only says that a subcommand is required.
std::string unknownCommandMessage(CLI::App& cli, int argc, char** argv) {
    CLI::App* app = &cli;
    std::string path = "chcrt";
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word.empty() || word[0] == '-') return {};
        const std::vector<CLI::App*> commands = app->get_subcommands([](CLI::App*) { return true; });
        if (commands.empty()) return {};
        CLI::App* next = nullptr;
        std::string names, nearest;
        size_t best = 3; // suggest only names within two edits
        for (CLI::App* c : commands) {
            if (c->get_name() == word) next = c;
            names += (names.empty() ? "" : ", ") + c->get_name();
            const size_t d = editDistance(word, c->get_name());
            if (d < best) best = d, nearest = c->get_name();
        }
        if (!next) {
            return "unknown command '" + word + "' of " + path + (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
                   "; commands: " + names;
        }
        app = next;
        path += " " + word;
    }
    return {};
}

} // namespace

std::optional<int> parseCommandLine(CLI::App& cli, int argc, char** argv) {
    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        const std::string unknown = unknownCommandMessage(cli, argc, argv);
        std::fprintf(stderr, "chcrt: error: %s (see chcrt --help)\n", unknown.empty() ? e.what() : unknown.c_str());
        return kExitBadInput;
    }
    return std::nullopt;
}

ViewOptions::ViewOptions() {
    common.render.width = 1280;
    common.render.height = 720;
    common.render.samplesPerPixel = 1;
    common.render.effects = EffectSet{true, false, false}; // interactive on a CPU rasteriser; the panel adds AO, diffuse
}

void addViewOptions(CLI::App& c, ViewOptions& view) {
    addCommonOptions(c, view.common, kShadedCommands); // no --gl: the viewer's context is its GLFW window
    c.add_option("--method", view.method, "Tracing method: raster (no secondary rays) or a GPU method (" +
                                              methodNames(false) + ")")
        ->capture_default_str();
    std::string modes;
    for (ViewMode mode : allViewModes()) modes += (modes.empty() ? "" : ", ") + std::string(toString(mode));
    c.add_option("--view-mode", view.viewMode, modes)->capture_default_str();
    c.add_option("--render-scale", view.renderScale, "Internal resolution / window resolution")->capture_default_str();
    c.add_option("--script", view.script, "Run a scripted session (JSON list of steps) and exit");
    c.add_option("--record", view.recordFile, "Where recorded walkthroughs are saved")->capture_default_str();
    c.add_flag("--play", view.play, "Start playing the camera path");
    c.add_flag("--no-accumulate", view.noAccumulate, "No progressive refinement when the camera stops");
    c.add_flag("--hide-panel", view.hidePanel, "Start with the ImGui panel hidden (Tab toggles it)");
    addResourceLogOptions(c, view.resourceLog, view.resourceEvery);
}

void addResourceLogOptions(CLI::App& c, std::string& file, int& every) {
    c.add_option("--resource-log", file,
                 "Write a JSON line of resident memory, open files, threads and live GL objects every "
                 "--resource-every frames (long runs; scripts/soak.sh)");
    c.add_option("--resource-every", every, "Frames between two --resource-log lines")
        ->check(CLI::Range(1, 1000000000))
        ->capture_default_str();
}

void checkViewOptions(const ViewOptions& view) {
    (void)toRenderSettings(view.common, view.common.render.samplesPerPixel);
    if (!(view.renderScale >= 0.05f && view.renderScale <= 2.0f)) throw InputError("--render-scale must be in [0.05, 2]");
}

} // namespace chcrt::app
