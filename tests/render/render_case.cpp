// SPDX-License-Identifier: Apache-2.0
#include "render_case.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "navmap/map/guidance/maneuver.h"
#include "test_paths.h"

namespace navmap::test {

namespace {

using Json = nlohmann::json;
using render::MapLayers;

// What is wrong with the case file; thrown inside the loader only and returned as its error.
struct CaseProblem {
    std::string what;
};

std::string quoted(const std::string& where, const std::string& key) {
    return "\"" + (where.empty() ? key : where + "." + key) + "\"";
}

void onlyKeys(const Json& object, const std::string& where, std::initializer_list<const char*> known) {
    for (auto it = object.begin(); it != object.end(); ++it) {
        if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
        std::string list;
        for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
        throw CaseProblem{"unknown key " + quoted(where, it.key()) + " (known: " + list + ")"};
    }
}

const Json* find(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

const Json& required(const Json& object, const char* key, const std::string& where) {
    const Json* v = find(object, key);
    if (!v) throw CaseProblem{quoted(where, key) + " is missing"};
    return *v;
}

const Json& objectAt(const Json& object, const char* key, const std::string& where) {
    const Json& v = required(object, key, where);
    if (!v.is_object()) throw CaseProblem{quoted(where, key) + " must be an object"};
    return v;
}

double number(const Json& object, const char* key, const std::string& where, double lo, double hi, double fallback) {
    const Json* v = find(object, key);
    if (!v) return fallback;
    if (!v->is_number() || !std::isfinite(v->get<double>()) || v->get<double>() < lo || v->get<double>() > hi) {
        std::ostringstream range;
        range << lo << " to " << hi;
        throw CaseProblem{quoted(where, key) + " must be a number from " + range.str()};
    }
    return v->get<double>();
}

long long integer(const Json& v, const std::string& name, long long lo, long long hi) {
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
        throw CaseProblem{name + " must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi)};
    return v.get<long long>();
}

int integer(const Json& object, const char* key, const std::string& where, int lo, int hi, int fallback) {
    const Json* v = find(object, key);
    return v ? static_cast<int>(integer(*v, quoted(where, key), lo, hi)) : fallback;
}

std::string text(const Json& object, const char* key, const std::string& where, const std::string& fallback) {
    const Json* v = find(object, key);
    if (!v) return fallback;
    if (!v->is_string()) throw CaseProblem{quoted(where, key) + " must be a string"};
    return v->get<std::string>();
}

template <typename E>
E choice(const Json& object, const char* key, const std::string& where,
         std::initializer_list<std::pair<const char*, E>> names, E fallback) {
    const Json* v = find(object, key);
    if (!v) return fallback;
    std::string list;
    for (const auto& [n, e] : names) {
        if (v->is_string() && v->get<std::string>() == n) return e;
        list += std::string(list.empty() ? "" : ", ") + "\"" + n + "\"";
    }
    throw CaseProblem{quoted(where, key) + " must be one of " + list};
}

// The boolean switches of MapLayers, by their key in case.json.
constexpr std::pair<const char*, bool MapLayers::*> kLayerSwitches[] = {
    {"terrain", &MapLayers::terrain},
    {"far_ground", &MapLayers::far_ground},
    {"land_cover", &MapLayers::land_cover},
    {"roads", &MapLayers::roads},
    {"outlines", &MapLayers::outlines},
    {"outlines_near_roads", &MapLayers::outlines_near_roads},
    {"cull_blocks", &MapLayers::cull_blocks},
    {"cull_hidden_roads", &MapLayers::cull_hidden_roads},
    {"road_lod", &MapLayers::road_lod},
    {"road_selection", &MapLayers::road_selection},
    {"trim_joint_caps", &MapLayers::trim_joint_caps},
    {"buildings", &MapLayers::buildings},
    {"route", &MapLayers::route},
    {"marker", &MapLayers::marker},
    {"labels", &MapLayers::labels},
    {"glow_roads", &MapLayers::glow_roads},
    {"glow_blur", &MapLayers::glow_blur},
    {"label_aura", &MapLayers::label_aura},
};

MapLayers readLayers(const Json& object) {
    const std::string where = "layers";
    const Json& j = objectAt(object, "layers", "");
    enum class Preset { Default, Hud };
    const Preset preset =
        choice(j, "preset", where, {{"default", Preset::Default}, {"hud", Preset::Hud}}, Preset::Default);
    MapLayers layers = preset == Preset::Hud ? MapLayers::hud() : MapLayers{};
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& key = it.key();
        if (key == "preset" || key == "glow_mode" || key == "road_technique" || key == "outline_mask") continue;
        const auto* sw = std::find_if(std::begin(kLayerSwitches), std::end(kLayerSwitches),
                                      [&](const auto& s) { return key == s.first; });
        if (sw == std::end(kLayerSwitches)) {
            std::string list = "preset, glow_mode, road_technique, outline_mask";
            for (const auto& s : kLayerSwitches) list += std::string(", ") + s.first;
            throw CaseProblem{"unknown key " + quoted(where, key) + " (known: " + list + ")"};
        }
        if (!it->is_boolean()) throw CaseProblem{quoted(where, key) + " must be true or false"};
        layers.*(sw->second) = it->get<bool>();
    }
    using GlowMode = MapLayers::GlowMode;
    using OutlineMask = MapLayers::OutlineMask;
    using render::RoadTechnique;
    layers.glow_mode =
        choice(j, "glow_mode", where, {{"single_color", GlowMode::SingleColor}, {"road_color", GlowMode::RoadColor}},
               layers.glow_mode);
    layers.road_technique = choice(j, "road_technique", where,
                                   {{"geometric", RoadTechnique::Geometric},
                                    {"shadow_volume", RoadTechnique::ShadowVolume},
                                    {"auto", RoadTechnique::Auto}},
                                   layers.road_technique);
    layers.outline_mask = choice(j, "outline_mask", where,
                                 {{"auto", OutlineMask::Auto}, {"gpu", OutlineMask::Gpu}, {"cpu", OutlineMask::Cpu}},
                                 layers.outline_mask);
    return layers;
}

CaseStats readStats(const Json& object, const std::string& where) {
    CaseStats stats;
    const Json* j = find(object, "stats");
    if (!j) return stats;
    if (!j->is_object()) throw CaseProblem{quoted(where, "stats") + " must be an object"};
    const std::string at = where.empty() ? "stats" : where + ".stats";
    onlyKeys(*j, at, {"at_least", "equal"});
    const render::MapFrameStats none;
    if (const Json* least = find(*j, "at_least")) {
        if (!least->is_object()) throw CaseProblem{quoted(at, "at_least") + " must be an object"};
        for (auto it = least->begin(); it != least->end(); ++it) {
            const std::string name = quoted(at + ".at_least", it.key());
            if (!countStat(none, it.key())) throw CaseProblem{name + " is no count of the frame statistics"};
            stats.at_least[it.key()] = static_cast<std::size_t>(integer(*it, name, 0, 1LL << 40));
        }
    }
    if (const Json* equal = find(*j, "equal")) {
        if (!equal->is_object()) throw CaseProblem{quoted(at, "equal") + " must be an object"};
        for (auto it = equal->begin(); it != equal->end(); ++it) {
            const std::string name = quoted(at + ".equal", it.key());
            if (!flagStat(none, it.key())) throw CaseProblem{name + " is no flag of the frame statistics"};
            if (!it->is_boolean()) throw CaseProblem{name + " must be true or false"};
            stats.equal[it.key()] = it->get<bool>();
        }
    }
    return stats;
}

std::optional<CaseGuidance> readGuidance(const Json& object) {
    const Json* j = find(object, "guidance");
    if (!j) return std::nullopt;
    if (!j->is_object()) throw CaseProblem{"\"guidance\" must be an object"};
    onlyKeys(*j, "guidance", {"junction_m", "arrow", "junction_roads_radius_m", "overlay"});
    CaseGuidance g;
    required(*j, "junction_m", "guidance");
    g.junction_m = number(*j, "junction_m", "guidance", 0.0, 1e7, 0.0);
    if (find(*j, "arrow")) {
        const Json& a = objectAt(*j, "arrow", "guidance");
        onlyKeys(a, "guidance.arrow", {"before_m", "after_m"});
        g.arrow = true;
        g.arrow_before_m = number(a, "before_m", "guidance.arrow", 0.0, 1000.0, g.arrow_before_m);
        g.arrow_after_m = number(a, "after_m", "guidance.arrow", 0.0, 1000.0, g.arrow_after_m);
    }
    if (find(*j, "junction_roads_radius_m"))
        g.junction_roads_radius_m = number(*j, "junction_roads_radius_m", "guidance", 1.0, 1000.0, 0.0);
    if (find(*j, "overlay")) {
        const std::string where = "guidance.overlay";
        const Json& o = objectAt(*j, "overlay", "guidance");
        onlyKeys(o, where, {"symbol", "roundabout_exit", "distance", "street", "remaining_distance", "remaining_time"});
        render::GuidanceOverlay overlay;
        const std::string symbol = text(o, "symbol", where, "straight");
        const auto type = map::guidance::maneuverTypeFromName(symbol);
        if (!type) throw CaseProblem{quoted(where, "symbol") + ": \"" + symbol + "\" is no manoeuvre (turn_left, ...)"};
        overlay.symbol = *type;
        overlay.roundabout_exit = integer(o, "roundabout_exit", where, 0, 32, 0);
        overlay.distance = text(o, "distance", where, "");
        overlay.street = text(o, "street", where, "");
        overlay.remaining_distance = text(o, "remaining_distance", where, "");
        overlay.remaining_time = text(o, "remaining_time", where, "");
        g.overlay = overlay;
    }
    return g;
}

void readDrive(const Json& j, RenderCase& c) {
    c.view = choice(j, "view", "", {{"bird", render::ViewMode::Bird}, {"snail", render::ViewMode::Snail}},
                    render::ViewMode::Bird);
    required(j, "view", "");
    const Json& pose = objectAt(j, "pose", "");
    onlyKeys(pose, "pose", {"measure_m", "speed_mps"});
    required(pose, "measure_m", "pose");
    c.measure_m = number(pose, "measure_m", "pose", 0.0, 1e7, c.measure_m);
    c.speed_mps = number(pose, "speed_mps", "pose", 0.0, 100.0, c.speed_mps);
    c.style = choice<std::string>(j, "style", "", {{"day", "day"}, {"night", "night"}, {"hud", "hud"}}, "day");
    if (find(j, "layers")) c.layers = readLayers(j);
    c.frames = integer(j, "frames", "", 1, 600, 1);
    c.guidance = readGuidance(j);
}

void readHeightfield(const Json& j, RenderCase& c) {
    c.hgt = text(j, "hgt", "", "");
    required(j, "hgt", "");
    if (c.hgt.empty() || c.hgt.find('/') != std::string::npos || c.hgt.starts_with("."))
        throw CaseProblem{"\"hgt\" must name a file in data/ (no path)"};
    c.camera = choice<std::string>(j, "camera", "", {{"andorra_overview", "andorra_overview"}}, "");
    required(j, "camera", "");
}

void readTolerance(const Json& j, RenderCase& c) {
    const Json& t = objectAt(j, "tolerance", "");
    onlyKeys(t, "tolerance", {"channel", "max_differing_fraction"});
    required(t, "channel", "tolerance");
    required(t, "max_differing_fraction", "tolerance");
    c.tolerance.channel = integer(t, "channel", "tolerance", 0, 255, 0);
    c.tolerance.max_differing_fraction = number(t, "max_differing_fraction", "tolerance", 0.0, 1.0, 0.0);
}

void readFallback(const Json& j, RenderCase& c) {
    if (!find(j, "fallback")) return;
    const Json& f = objectAt(j, "fallback", "");
    onlyKeys(f, "fallback", {"feature_off", "expected_case", "stats"});
    CaseFallback fallback;
    required(f, "feature_off", "fallback");
    required(f, "expected_case", "fallback");
    fallback.feature_off = text(f, "feature_off", "fallback", "");
    fallback.expected_case = text(f, "expected_case", "fallback", "");
    if (fallback.feature_off.empty()) throw CaseProblem{"\"fallback.feature_off\" must not be empty"};
    if (caseTestName(fallback.expected_case) != fallback.expected_case || fallback.expected_case.empty())
        throw CaseProblem{"\"fallback.expected_case\" must name a case directory beside this one"};
    fallback.stats = readStats(f, "fallback");
    c.fallback = fallback;
}

RenderCase readCase(const Json& j, const std::filesystem::path& dir) {
    if (!j.is_object()) throw CaseProblem{"must hold a JSON object"};
    RenderCase c;
    c.dir = dir;
    c.name = dir.filename().string();
    c.description = text(j, "description", "", "");
    required(j, "scene", "");
    c.scene =
        choice(j, "scene", "", {{"andorra_drive", CaseScene::AndorraDrive}, {"heightfield", CaseScene::Heightfield}},
               CaseScene::AndorraDrive);
    if (c.scene == CaseScene::AndorraDrive) {
        onlyKeys(j, "",
                 {"description", "scene", "size", "msaa", "tolerance", "stats", "fallback", "view", "pose", "style",
                  "layers", "frames", "guidance"});
        readDrive(j, c);
    } else {
        onlyKeys(j, "", {"description", "scene", "size", "msaa", "tolerance", "hgt", "camera"});
        readHeightfield(j, c);
    }
    const Json& size = required(j, "size", "");
    if (!size.is_array() || size.size() != 2) throw CaseProblem{"\"size\" must be [width, height]"};
    c.width = static_cast<int>(integer(size[0], "\"size\" width", 1, 4096));
    c.height = static_cast<int>(integer(size[1], "\"size\" height", 1, 4096));
    c.msaa_samples = integer(j, "msaa", "", -1, 16, -1);
    readTolerance(j, c);
    c.stats = readStats(j, "");
    readFallback(j, c);
    return c;
}

}  // namespace

std::filesystem::path RenderCase::expectedPath(const std::string& case_name) const {
    return (case_name.empty() ? dir : dir.parent_path() / case_name) / "expected.png";
}

std::optional<RenderCase> loadRenderCase(const std::filesystem::path& dir, std::string* error) {
    const std::filesystem::path file = dir / "case.json";
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        *error = file.string() + ": cannot be read (a case directory holds case.json and expected.png)";
        return std::nullopt;
    }
    std::ostringstream content;
    content << in.rdbuf();
    try {
        return readCase(Json::parse(content.str()), dir);
    } catch (const Json::parse_error& e) {
        std::string what = e.what();
        if (const auto at = what.find("] "); what.starts_with("[json.exception") && at != std::string::npos)
            what = what.substr(at + 2);
        *error = file.string() + ": not JSON: " + what;
    } catch (const CaseProblem& p) {
        *error = file.string() + ": " + p.what;
    }
    return std::nullopt;
}

std::filesystem::path renderCasesDir() {
    if (const char* dir = std::getenv("NAVMAP_RENDER_CASES"); dir && *dir) return dir;
    return sourceDir() / "tests" / "render" / "cases";
}

std::vector<std::filesystem::path> listRenderCases(const std::filesystem::path& root) {
    std::vector<std::filesystem::path> dirs;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(root, ec)) {
        if (entry.is_directory(ec)) dirs.push_back(entry.path());
    }
    std::sort(dirs.begin(), dirs.end());
    return dirs;
}

std::string caseTestName(const std::string& dir_name) {
    std::string name = dir_name;
    for (char& ch : name) {
        const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_';
        if (!ok) ch = '_';
    }
    return name;
}

std::optional<std::size_t> countStat(const render::MapFrameStats& stats, const std::string& name) {
    if (name == "tiles_drawn") return stats.tiles_drawn;
    if (name == "road_segments") return stats.road_segments;
    if (name == "building_triangles") return stats.building_triangles;
    if (name == "terrain_triangles") return stats.terrain_triangles;
    if (name == "labels_visible") return stats.labels_visible;
    if (name == "label_glyphs") return stats.label_glyphs;
    return std::nullopt;
}

std::optional<bool> flagStat(const render::MapFrameStats& stats, const std::string& name) {
    if (name == "sv_roads") return stats.sv_roads;
    if (name == "outline_mask_on_cpu") return stats.outline_mask_on_cpu;
    return std::nullopt;
}

glm::dvec3 routeAt(const render::RouteGeometry& r, double m) {
    const auto it = std::upper_bound(r.measure_m.begin(), r.measure_m.end(), m);
    const auto i = static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>(it - r.measure_m.begin(), 1, std::ptrdiff_t(r.points.size()) - 1));
    const double t =
        std::clamp((m - r.measure_m[i - 1]) / std::max(r.measure_m[i] - r.measure_m[i - 1], 1e-9), 0.0, 1.0);
    return r.points[i - 1] + t * (r.points[i] - r.points[i - 1]);
}

}  // namespace navmap::test
