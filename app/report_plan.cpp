#include "app/report_plan.h"

#include "app/commands.h"
#include "app/methods.h"
#include "renderer/core/error.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/camera_path.h"
#include "renderer/scene/procedural/procedural.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace chcrt::app {

const std::vector<std::string>& reportStudies() {
    static const std::vector<std::string> studies = {"compare", "aggressive", "rotation", "work",  "ls-rc",
                                                     "ls-ao",   "ls-ss",      "ls-sscand", "ls-ntree", "images"};
    return studies;
}

std::string presetNames() { return "quick, paper, linespace"; }

ReportSettings presetSettings(const std::string& preset) {
    ReportSettings s;
    s.paths = {"near"};
    s.rayTypes = {"primary", "shadow", "ao", "diffuse"};
    s.spp = {{"primary", 1}, {"shadow", 1}, {"ao", 1}, {"diffuse", 1}};
    s.aggressiveRayTypes = {"primary", "ao"};
    s.rotationRayTypes = {"ao", "diffuse"};
    s.heights = {"24", "18", "14", "10", "8", "6"};
    s.lsDepths = {"6", "9"};
    s.lsSsN = {"4", "6"};
    s.lsNtree = {"4:4", "6:3", "8:3"};
    s.lsSsCandidate = {"7:11", "8:11"};
    if (preset == "quick") {
        // Small enough for a few minutes on two cores, large enough that culling has something to cull.
        s.scenes = {"city:200k", "interior:200k", "plant:200k"};
        s.methods = {"bvh", "chcrt", "chcrt-noadapt", "chcrt-aggressive", "bvh+ls"};
        s.studies = {"compare", "aggressive", "rotation", "ls-rc", "images"};
        s.thresholds = {"0", "20", "100"};
        s.rotations = {"0", "36", "360"};
        s.lsDepths = {"3", "6"};
        s.singleViewRuns = 3;
        return s;
    }
    if (preset == "paper") {
        // scripts/bench_chcrt.sh's tables: CHC+RT Table 2 (and Figure 8), Table 4, Table 5, at the paper's spp.
        s.scenes = {"city", "interior", "plant"};
        s.paths = {"near", "far"};
        s.methods = {"bvh", "chcrt", "chcrt-noadapt"};
        s.studies = {"compare", "aggressive", "rotation", "images"};
        s.size = 256;
        s.frames = "0-15";
        s.runs = 1;
        s.spp = {{"primary", 1}, {"shadow", 16}, {"ao", 20}, {"diffuse", 20}};
        s.thresholds = {"0", "20", "100", "200"};
        s.rotations = {"0", "18", "36", "360"};
        s.imageSpp = 4;
        return s;
    }
    if (preset == "linespace") {
        // scripts/bench_linespace.sh's tables: RC Table 1 and SS Table 1 shapes, N-tree rows.
        s.scenes = {"city", "interior"};
        s.methods = {"bvh", "bvh+ls"};
        s.studies = {"ls-rc", "ls-ss", "ls-ntree"};
        s.size = 256;
        s.frames = "0,5";
        s.runs = 3;
        s.singleViewRuns = 3;
        s.steps = false;
        return s;
    }
    throw InputError("--preset " + preset + ": unknown preset (" + presetNames() + ")");
}

std::string sceneLabel(const std::string& scene) {
    std::string name = scene;
    ProceduralSpec spec;
    bool generated = false;
    try {
        generated = parseProceduralSpec(scene, spec);
    } catch (const InputError&) {
    }
    if (!generated) name = std::filesystem::path(scene).stem().string();
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.') c = '-';
    }
    return name;
}

namespace {

// One camera of a scene: a walkthrough or a single view.
struct SceneView {
    std::string scene, cameraPath, label;
    bool single = false; // one frame: a scene file's default camera or a one-keyframe path
};

SceneView viewOf(const std::string& scene, bool generated, const std::string& path) {
    if (path == "near" || path == "far") {
        if (!generated) throw InputError("--scenes " + scene + "@" + path + ": near and far exist for generated scenes only");
        return {scene, path, path, false};
    }
    if (!std::filesystem::exists(path)) throw InputError("--paths " + path + ": not near, far or an existing camera path file");
    const CameraPath camera = loadCameraPath(path);
    return {scene, path, std::filesystem::path(path).stem().string(), camera.frameCount() == 1};
}

std::vector<SceneView> viewsOf(const std::string& entry, const ReportSettings& s) {
    const size_t at = entry.rfind('@');
    const std::string scene = entry.substr(0, at);
    ProceduralSpec spec;
    const bool generated = parseProceduralSpec(scene, spec); // throws for a malformed spec
    if (!generated && !std::filesystem::is_regular_file(scene)) {
        throw InputError("--scenes " + scene + ": neither a generator spec (city, interior, plant, ...) nor a file");
    }
    if (at != std::string::npos) return {viewOf(scene, generated, entry.substr(at + 1))};
    if (!generated) return {{scene, "", "default", true}};
    std::vector<SceneView> views;
    for (const std::string& p : s.paths) views.push_back(viewOf(scene, generated, p));
    return views;
}

void checkNumbers(const std::vector<std::string>& values, const char* flag) {
    for (const std::string& v : values) {
        if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos) {
            throw InputError(std::string(flag) + " " + v + ": not a non-negative integer");
        }
    }
}

void checkPairs(const std::vector<std::string>& values, const char* flag) {
    for (const std::string& v : values) {
        const size_t colon = v.find(':');
        if (colon == std::string::npos) throw InputError(std::string(flag) + " " + v + ": expected N:d");
        checkNumbers({v.substr(0, colon), v.substr(colon + 1)}, flag);
    }
}

// Frames a --frames expression selects, roughly (the ETA's weights; the bench resolves the real list).
double approximateFrames(const std::string& frames) {
    double count = 0;
    size_t start = 0;
    while (start <= frames.size()) {
        const size_t comma = std::min(frames.find(',', start), frames.size());
        const std::string item = frames.substr(start, comma - start);
        const size_t dash = item.find('-'), colon = item.find(':');
        if (item.rfind("spread:", 0) == 0) count += std::atof(item.c_str() + 7);
        else if (item.rfind("all", 0) == 0) count += 16;
        else if (dash != std::string::npos) {
            const double step = colon == std::string::npos ? 1 : std::max(1.0, std::atof(item.c_str() + colon + 1));
            count += (std::atof(item.c_str() + dash + 1) - std::atof(item.c_str())) / step + 1;
        } else count += 1;
        start = comma + 1;
    }
    return std::max(1.0, count);
}

// Builds the groups of one report.
struct Planner {
    const ReportSettings& s;
    std::string outDir;
    std::vector<ReportGroup> groups;

    std::vector<std::string> viewArgs(const SceneView& v, bool bench) const {
        std::vector<std::string> a = {"-q", "--scene", v.scene};
        if (!v.cameraPath.empty()) a.insert(a.end(), {"--camera-path", v.cameraPath});
        a.insert(a.end(), {"--width", std::to_string(s.size), "--height", std::to_string(s.size)});
        if (bench) {
            a.insert(a.end(), {"--frames", v.single ? "0" : s.frames, "--runs",
                               std::to_string(v.single ? s.singleViewRuns : s.runs), "--warmup", std::to_string(s.warmup)});
        }
        if (!s.gl.empty()) a.insert(a.end(), {"--gl", s.gl});
        if (!s.lsCache.empty()) a.insert(a.end(), {"--ls-cache", s.lsCache});
        return a;
    }

    // A bench writing data/<id>.json: the view's flags, then the study's.
    void bench(const std::string& study, const SceneView& v, const std::string& suffix,
               const std::vector<std::string>& rayTypes, int spp, const std::vector<std::string>& methods,
               const std::vector<std::string>& extra) {
        ReportGroup g;
        g.study = study;
        std::string types;
        for (const std::string& t : rayTypes) types += (types.empty() ? "" : ",") + t;
        g.id = study + "_" + sceneLabel(v.scene) + "_" + v.label + (suffix.empty() ? "" : "_" + suffix) + "_" + types;
        std::replace(g.id.begin(), g.id.end(), ',', '-');
        std::string methodList;
        for (const std::string& m : methods) methodList += (methodList.empty() ? "" : ",") + m;
        g.label = study + " " + sceneLabel(v.scene) + " " + v.label + (suffix.empty() ? "" : " " + suffix) + " " + types;
        std::vector<std::string> c = {"bench"};
        const std::vector<std::string> view = viewArgs(v, true);
        c.insert(c.end(), view.begin(), view.end());
        c.insert(c.end(), {"--ray-type", types, "--spp", std::to_string(spp), "--method", methodList});
        c.insert(c.end(), extra.begin(), extra.end());
        c.insert(c.end(), {"--json", outDir + "/data/" + g.id + ".json"});
        g.commands.push_back(c);
        g.cost = approximateFrames(v.single ? "0" : s.frames) * (s.warmup + (v.single ? s.singleViewRuns : s.runs)) *
                 double(rayTypes.size()) * spp * double(methods.size());
        g.scene = v.scene;
        g.path = v.label;
        groups.push_back(std::move(g));
    }

    // One bench per spp value (bench takes one --spp for all its ray types).
    void benchBySpp(const std::string& study, const SceneView& v, const std::string& suffix,
                    const std::vector<std::string>& rayTypes, const std::vector<std::string>& methods,
                    const std::vector<std::string>& extra) {
        std::vector<int> spps;
        for (const std::string& t : rayTypes) {
            if (std::find(spps.begin(), spps.end(), s.spp.at(t)) == spps.end()) spps.push_back(s.spp.at(t));
        }
        for (int spp : spps) {
            std::vector<std::string> types;
            for (const std::string& t : rayTypes) if (s.spp.at(t) == spp) types.push_back(t);
            bench(study, v, suffix, types, spp, methods, extra);
        }
    }

    void images(const SceneView& v, const std::vector<std::string>& approximate);
};

bool hasStudy(const ReportSettings& s, const char* study) {
    return std::find(s.studies.begin(), s.studies.end(), study) != s.studies.end();
}

void Planner::images(const SceneView& v, const std::vector<std::string>& approximate) {
    ReportGroup g;
    g.study = "images";
    g.images = true;
    g.id = "images_" + sceneLabel(v.scene) + "_" + v.label;
    g.label = "images " + sceneLabel(v.scene) + " " + v.label;
    g.scene = v.scene;
    g.path = v.label;
    g.frame = std::atoi(s.frames.c_str()); // the first frame of the walkthrough's selection
    if (v.single) g.frame = 0;
    std::vector<std::string> view = viewArgs(v, false);
    view.insert(view.end(), {"--frames", std::to_string(g.frame), "--spp", std::to_string(s.imageSpp)});
    auto render = [&](const std::string& key, const std::string& method, const std::string& debug,
                      const std::string& queries) {
        const std::string file = "images/" + g.id + "_" + key + ".png";
        std::vector<std::string> c = {"render"};
        c.insert(c.end(), view.begin(), view.end());
        c.insert(c.end(), {"--method", method});
        if (!debug.empty()) c.insert(c.end(), {"--debug-image", debug});
        if (!queries.empty()) c.insert(c.end(), {"--chcrt-queries", queries});
        c.insert(c.end(), {"-o", outDir + "/" + file});
        g.commands.push_back(c);
        g.files[key] = file;
    };
    render("bvh", kPureBvhMethod, "", "");
    // chcrt-noadapt: the debug images show culling, which the adaptive chcrt may skip for a pure pass.
    // Overdraw counts GL query fragments, which bounds-only pair decisions (chcrt-noadapt's default) never draw.
    for (const char* debug : {"overdraw", "subtrees", "batches", "cost"}) {
        render(debug, "chcrt-noadapt", debug, std::string(debug) == "overdraw" ? "gl" : "");
    }
    for (const std::string& m : approximate) render(m, m, "", "");
    g.cost = double(g.commands.size()) * s.imageSpp * 4;
    groups.push_back(std::move(g));
}

void addUnique(std::vector<std::string>& list, const std::string& item) {
    if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

std::vector<std::string> subset(const std::vector<std::string>& wanted, const std::vector<std::string>& available) {
    std::vector<std::string> out;
    for (const std::string& t : wanted) {
        if (std::find(available.begin(), available.end(), t) != available.end()) out.push_back(t);
    }
    return out;
}

void checkSettings(const ReportSettings& s) {
    for (const std::string& m : s.methods) findMethod(m); // throws listing the methods
    for (const std::string& t : s.rayTypes) {
        parseRayType(t);
        if (!s.spp.count(t)) throw InputError("--spp: no samples per pixel for ray type " + t);
    }
    for (const std::string& study : s.studies) {
        if (std::find(reportStudies().begin(), reportStudies().end(), study) == reportStudies().end()) {
            std::string names;
            for (const std::string& n : reportStudies()) names += (names.empty() ? "" : ", ") + n;
            throw InputError("--studies " + study + ": unknown study (" + names + ")");
        }
    }
    if (s.size < 1 || s.runs < 1 || s.warmup < 0 || s.singleViewRuns < 1 || s.lsSpp < 1 || s.imageSpp < 1) {
        throw InputError("--size, --runs, --single-view-runs and samples per pixel must be at least 1, --warmup 0");
    }
    checkNumbers(s.thresholds, "--thresholds");
    checkNumbers(s.rotations, "--rotations");
    checkNumbers(s.heights, "--heights");
    checkNumbers(s.lsDepths, "--ls-depths");
    checkNumbers(s.lsSsN, "--ls-ss-n");
    checkPairs(s.lsNtree, "--ls-ntree");
    checkPairs(s.lsSsCandidate, "--ls-ss-candidate");
}

} // namespace

namespace {

std::vector<std::string> listOr(const std::string& given, const std::vector<std::string>& preset) {
    return given.empty() ? preset : splitList(given);
}

// --spp N (every ray type) or type=N,... (those types).
void applySpp(const std::string& text, std::map<std::string, int>& spp) {
    for (const std::string& item : splitList(text)) {
        const size_t eq = item.find('=');
        const std::string value = eq == std::string::npos ? item : item.substr(eq + 1);
        checkNumbers({value}, "--spp");
        const int n = std::atoi(value.c_str());
        if (n < 1) throw InputError("--spp " + item + ": at least 1");
        if (eq == std::string::npos) {
            for (auto& [type, v] : spp) v = n;
        } else {
            const std::string type = item.substr(0, eq);
            parseRayType(type);
            spp[type] = n;
        }
    }
}

} // namespace

ReportSettings reportSettings(const ReportOptions& o) {
    ReportSettings s = presetSettings(o.preset);
    s.scenes = listOr(o.scenes, s.scenes);
    s.paths = listOr(o.paths, s.paths);
    s.methods = listOr(o.methods, s.methods);
    s.rayTypes = listOr(o.rayTypes, s.rayTypes);
    s.studies = listOr(o.studies, s.studies);
    s.thresholds = listOr(o.thresholds, s.thresholds);
    s.rotations = listOr(o.rotations, s.rotations);
    s.heights = listOr(o.heights, s.heights);
    s.lsDepths = listOr(o.lsDepths, s.lsDepths);
    s.lsSsN = listOr(o.lsSsN, s.lsSsN);
    s.lsNtree = listOr(o.lsNtree, s.lsNtree);
    s.lsSsCandidate = listOr(o.lsSsCandidate, s.lsSsCandidate);
    if (!o.frames.empty()) s.frames = o.frames;
    if (!o.spp.empty()) applySpp(o.spp, s.spp);
    if (!o.lsCache.empty()) s.lsCache = o.lsCache;
    if (!o.gl.empty()) s.gl = o.gl;
    for (auto [given, field] : {std::pair{o.size, &s.size}, {o.runs, &s.runs}, {o.warmup, &s.warmup},
                                {o.singleViewRuns, &s.singleViewRuns}, {o.lsSpp, &s.lsSpp}, {o.lsN, &s.lsN},
                                {o.lsSsDepth, &s.lsSsDepth}, {o.lsNtreeNear, &s.lsNtreeNear}}) {
        if (given >= 0) *field = given;
    }
    return s;
}

std::vector<ReportGroup> planReport(const ReportSettings& s, const std::string& outDir) {
    checkSettings(s);
    Planner p{s, outDir, {}};
    std::vector<std::vector<SceneView>> scenes;
    for (const std::string& entry : s.scenes) scenes.push_back(viewsOf(entry, s));
    std::vector<std::string> approximate; // methods whose frames the images study shows next to pure BVH's
    for (const std::string& m : s.methods) if (!findMethod(m).exact && findMethod(m).gpu) addUnique(approximate, m);
    if (hasStudy(s, "aggressive")) addUnique(approximate, "chcrt-aggressive");
    if (hasStudy(s, "ls-rc")) addUnique(approximate, "bvh+ls");
    std::vector<std::string> compareMethods = {kPureBvhMethod};
    for (const std::string& m : s.methods) addUnique(compareMethods, m);
    const std::vector<std::string> steps = s.steps ? std::vector<std::string>{"--steps"} : std::vector<std::string>{};
    const int lsSpp = s.lsSpp;
    for (const std::vector<SceneView>& views : scenes) {
        if (hasStudy(s, "compare")) {
            for (const SceneView& v : views) p.benchBySpp("compare", v, "", s.rayTypes, compareMethods, steps);
        }
        const SceneView& v = views.front(); // the sweeps run on the scene's first path
        for (const std::string& t : s.thresholds) {
            if (!hasStudy(s, "aggressive")) break;
            p.benchBySpp("aggressive", v, "t" + t, subset(s.aggressiveRayTypes, s.rayTypes),
                         {kPureBvhMethod, "chcrt-aggressive"}, {"--chcrt-threshold", t});
        }
        for (const std::string& r : s.rotations) {
            if (!hasStudy(s, "rotation")) break;
            p.benchBySpp("rotation", v, "r" + r, subset(s.rotationRayTypes, s.rayTypes),
                         {kPureBvhMethod, "chcrt", "chcrt-noadapt"}, {"--rotation", r});
        }
        for (const std::string& h : s.heights) {
            if (!hasStudy(s, "work")) break;
            p.bench("work", v, "h" + h, s.rayTypes, 1, {kPureBvhMethod, "chcrt-noadapt"}, {"--chcrt-height", h, "--steps"});
        }
        const std::string n = std::to_string(s.lsN);
        for (const std::string& d : s.lsDepths) {
            if (!hasStudy(s, "ls-rc")) break;
            p.bench("ls-rc", v, "D" + d, {"primary", "ao", "diffuse"}, lsSpp, {kPureBvhMethod, "bvh+ls-exact", "bvh+ls"},
                    {"--effects", "shadow,ao,diffuse", "--ls-n", n, "--ls-depth", d, "--ls-modes",
                     "shadow=exact,bounce=exact,ao=off"});
        }
        for (const std::string& d : s.lsDepths) {
            if (!hasStudy(s, "ls-ao")) break;
            for (const char* variant : {"both", "front-start", "exact-start"}) {
                const std::string mode = std::string(variant) == "exact-start" ? "candidate-exact-start" : "candidate";
                const std::string faces = std::string(variant) == "exact-start" ? "front-start" : variant;
                p.bench("ls-ao", v, "D" + d + "_" + variant, {"ao"}, lsSpp, {kPureBvhMethod, "bvh+ls"},
                        {"--effects", "shadow,ao,diffuse", "--ls-n", n, "--ls-depth", d, "--ls-modes",
                         "shadow=exact,bounce=exact,diffuse=exact,ao=" + mode + ",faces=" + faces});
            }
        }
        for (const std::string& nd : s.lsNtree) {
            if (!hasStudy(s, "ls-ntree")) break;
            std::string id = nd;
            std::replace(id.begin(), id.end(), ':', '-');
            p.bench("ls-ntree", v, id, {"shadow"}, 25, {kPureBvhMethod, "ntree+ls"},
                    {"--effects", "shadow", "--ls-ntree", nd, "--ls-ntree-start", "skip", "--ls-ntree-near",
                     std::to_string(s.lsNtreeNear)});
        }
        for (const std::string& sn : s.lsSsN) {
            if (!hasStudy(s, "ls-ss")) break;
            p.bench("ls-ss", v, "N" + sn, {"shadow"}, 25, {kPureBvhMethod, "bvh+ls"},
                    {"--effects", "shadow", "--ls-n", sn, "--ls-depth", std::to_string(s.lsSsDepth), "--ls-modes",
                     "shadow=shadow,bounce=shadow,ao=exact,diffuse=exact"});
        }
        for (const std::string& nd : s.lsSsCandidate) {
            if (!hasStudy(s, "ls-sscand")) break;
            const std::string sn = nd.substr(0, nd.find(':')), d = nd.substr(nd.find(':') + 1);
            p.bench("ls-sscand", v, "N" + sn + "_D" + d, {"shadow"}, 25, {kPureBvhMethod, "bvh+ls"},
                    {"--effects", "shadow", "--ls-n", sn, "--ls-depth", d, "--ls-modes",
                     "shadow=candidate,bounce=shadow,ao=exact,diffuse=exact"});
        }
        if (hasStudy(s, "images")) p.images(v, approximate);
    }
    return p.groups;
}

} // namespace chcrt::app
