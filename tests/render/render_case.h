// SPDX-License-Identifier: Apache-2.0
#pragma once
// A render test as data (MapLibre render-test style): tests/render/cases/<name>/ holds case.json
// (what to render and how closely it must match) and expected.png (the golden). The format is
// described in docs/architecture.md "Render cases". Loading checks every key and value and
// names the file and the problem; it never throws.

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "golden.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"

namespace navmap::test {

/// What a case renders: a settled frame of the Andorra drive (the default store built into the
/// build tree), or the heightfield of an SRTM file seen by a named camera.
enum class CaseScene { AndorraDrive, Heightfield };

/// The manoeuvre guidance of a drive frame at the junction `junction_m` along the route: the
/// arrow cut from the route there, the roads around it (the HUD style draws them) and the
/// guidance overlay. Each part is optional.
struct CaseGuidance {
    double junction_m = 0.0;
    bool arrow = false;
    double arrow_before_m = 40.0;
    double arrow_after_m = 25.0;
    std::optional<double> junction_roads_radius_m;
    std::optional<render::GuidanceOverlay> overlay;
};

/// Statistics of the last rendered frame the case requires.
struct CaseStats {
    std::map<std::string, std::size_t> at_least;  ///< count name -> minimum
    std::map<std::string, bool> equal;            ///< flag name -> value
};

/// What a context without a feature renders instead (docs/gles-profile.md): when an entry of
/// DeviceInfo::features_off starts with `feature_off`, the frame is compared with the expected
/// image of case `expected_case` and checked against `stats`.
struct CaseFallback {
    std::string feature_off;
    std::string expected_case;
    CaseStats stats;
};

struct RenderCase {
    std::string name;           ///< the directory's name
    std::filesystem::path dir;  ///< the case's directory
    std::string description;
    CaseScene scene = CaseScene::AndorraDrive;
    int width = 640, height = 240;
    int msaa_samples = -1;  ///< RendererOptions::msaa_samples
    // AndorraDrive
    render::ViewMode view = render::ViewMode::Bird;
    double measure_m = 1800.0;
    double speed_mps = 13.0;
    std::string style = "day";  ///< "day", "night" or "hud"
    render::MapLayers layers;
    int frames = 1;  ///< rendered in a row (labels fade in); the last one is compared
    std::optional<CaseGuidance> guidance;
    // Heightfield
    std::string hgt;     ///< file name in data/
    std::string camera;  ///< "andorra_overview"
    // Checks
    GoldenTolerance tolerance;
    CaseStats stats;
    std::optional<CaseFallback> fallback;

    /// expected.png of this case, or of `case_name` beside it.
    [[nodiscard]] std::filesystem::path expectedPath(const std::string& case_name = {}) const;
};

/// Reads and checks `dir`/case.json. On failure returns nothing and sets `*error` to
/// "<dir>/case.json: <what is wrong>".
std::optional<RenderCase> loadRenderCase(const std::filesystem::path& dir, std::string* error);

/// The directory the cases are listed from: $NAVMAP_RENDER_CASES, else tests/render/cases of
/// the source tree.
std::filesystem::path renderCasesDir();

/// The case directories under `root`, sorted by name (every subdirectory: one without a valid
/// case.json is a case that fails). Empty when `root` is no directory.
std::vector<std::filesystem::path> listRenderCases(const std::filesystem::path& root);

/// The frame statistics a case can name (the MapFrameStats fields of those names); nothing for
/// any other name.
std::optional<std::size_t> countStat(const render::MapFrameStats& stats, const std::string& name);
std::optional<bool> flagStat(const render::MapFrameStats& stats, const std::string& name);

/// A test name for a case directory's name: characters other than letters, digits and '_'
/// become '_'.
std::string caseTestName(const std::string& dir_name);

/// The point `m` metres along the route, between its vertices (a vertex's own point at its
/// measure): where the cases' junctions and the arrow tests' turns are.
glm::dvec3 routeAt(const render::RouteGeometry& r, double m);

}  // namespace navmap::test
