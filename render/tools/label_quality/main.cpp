// navmap-label-quality: replays a drive through the renderer and prints the label quality
// measured on the drawn frames as JSON, one object per camera or view (docs/labels.md "Measured
// quality"): a recorded trajectory with MapLibre-convention cameras, or the route Andorra la
// Vella -> Encamp with the camera rig.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "label_quality.h"

namespace {

void usage() {
    std::fprintf(stderr,
                 "usage: navmap-label-quality [--trajectory FILE] [--camera zoom=Z,pitch=P[,bearing=B]]...\n"
                 "                            [--view bird|snail|both] [--store PATH] [--frames N] [--settle N]\n"
                 "                            [--dt S] [--size WxH] [--start M] [--speed MPS] [--no-occlusion]\n"
                 "                            [--aura] [--glow]\n"
                 "  --trajectory FILE  replay these poses (data/drives/*-trajectory.json); needs --camera\n"
                 "  --camera SPEC      MapLibre GL JS camera centred on the vehicle (512-px tiles, pitch from\n"
                 "                     straight down, fov 36.87); repeat for several; with a route drive the\n"
                 "                     rig follows with it instead of --view\n");
}

bool positiveInt(const char* text, int& out) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (*text == '\0' || *end != '\0' || v < 0 || v > 1000000) return false;
    out = static_cast<int>(v);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    namespace nt = navmap::render::tools;
    nt::LabelQualityOptions o;
    o.store = NAVMAP_DEFAULT_STORE;
    std::string views = "both";
    std::vector<navmap::render::MapLibreFollow> cameras;
    for (int i = 1; i < argc; ++i) {
        const std::string_view a = argv[i];
        auto value = [&]() -> const char* {
            if (i + 1 >= argc) {
                usage();
                std::exit(2);
            }
            return argv[++i];
        };
        auto count = [&](const char* name) {
            int n = 0;
            if (!positiveInt(value(), n)) {
                std::fprintf(stderr, "navmap-label-quality: %s needs a whole number\n", name);
                std::exit(2);
            }
            return n;
        };
        if (a == "--store") o.store = value();
        else if (a == "--trajectory") o.trajectory = value();
        else if (a == "--camera") {
            std::string error;
            const auto camera = nt::parseCameraSpec(value(), &error);
            if (!camera) {
                std::fprintf(stderr, "navmap-label-quality: %s\n", error.c_str());
                return 2;
            }
            cameras.push_back(*camera);
        } else if (a == "--view") views = value();
        else if (a == "--frames") o.frames = count("--frames");
        else if (a == "--settle") o.settle_frames = count("--settle");
        else if (a == "--dt") o.dt_s = std::atof(value());
        else if (a == "--start") o.start_m = std::atof(value());
        else if (a == "--speed") o.speed_mps = std::atof(value());
        else if (a == "--no-occlusion") o.measure_occlusion = false;
        else if (a == "--aura") o.label_aura = true;
        else if (a == "--glow") o.glow_roads = true;
        else if (a == "--size") {
            if (std::sscanf(value(), "%dx%d", &o.width, &o.height) != 2) {
                usage();
                return 2;
            }
        } else if (a == "--help" || a == "-h") {
            usage();
            return 0;
        } else {
            usage();
            return 2;
        }
    }
    if (views != "bird" && views != "snail" && views != "both") {
        usage();
        return 2;
    }
    if (!o.trajectory.empty() && cameras.empty()) {
        std::fprintf(stderr, "navmap-label-quality: --trajectory needs at least one --camera zoom=Z,pitch=P\n");
        return 2;
    }
    try {
        std::vector<nt::LabelQualityOptions> runs;
        if (!cameras.empty()) {
            for (const auto& c : cameras) {
                runs.push_back(o);
                runs.back().camera = c;
            }
        } else {
            for (auto mode : {navmap::render::ViewMode::Bird, navmap::render::ViewMode::Snail}) {
                if (views != "both" && (mode == navmap::render::ViewMode::Bird) != (views == "bird")) continue;
                runs.push_back(o);
                runs.back().view = mode;
            }
        }
        std::string out = "[";
        for (std::size_t k = 0; k < runs.size(); ++k) {
            out += (k == 0 ? "" : ",\n ") + nt::toJson(nt::measureLabelQuality(runs[k]));
        }
        std::printf("%s]\n", out.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "navmap-label-quality: %s\n", e.what());
        return 1;
    }
    return 0;
}
