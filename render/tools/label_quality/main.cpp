// navmap-label-quality: replays a drive (Andorra la Vella -> Encamp by default) through the
// renderer per view and prints the label quality metrics as JSON (issue 4).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "label_quality.h"

namespace {

void usage() {
    std::fprintf(stderr,
                 "usage: navmap-label-quality [--store PATH] [--view bird|snail|both] [--frames N] [--settle N]\n"
                 "                            [--dt S] [--size WxH] [--start M] [--speed MPS]\n");
}

}  // namespace

int main(int argc, char** argv) {
    namespace nt = navmap::render::tools;
    nt::LabelQualityOptions o;
    o.store = NAVMAP_DEFAULT_STORE;
    std::string views = "both";
    for (int i = 1; i < argc; ++i) {
        const std::string_view a = argv[i];
        auto value = [&]() -> const char* {
            if (i + 1 >= argc) {
                usage();
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--store") o.store = value();
        else if (a == "--view") views = value();
        else if (a == "--frames") o.frames = std::atoi(value());
        else if (a == "--settle") o.settle_frames = std::atoi(value());
        else if (a == "--dt") o.dt_s = std::atof(value());
        else if (a == "--start") o.start_m = std::atof(value());
        else if (a == "--speed") o.speed_mps = std::atof(value());
        else if (a == "--size") {
            if (std::sscanf(value(), "%dx%d", &o.width, &o.height) != 2) {
                usage();
                return 2;
            }
        } else {
            usage();
            return 2;
        }
    }
    if (views != "bird" && views != "snail" && views != "both") {
        usage();
        return 2;
    }
    try {
        std::string out = "[";
        bool first = true;
        for (auto mode : {navmap::render::ViewMode::Bird, navmap::render::ViewMode::Snail}) {
            if (views != "both" && (mode == navmap::render::ViewMode::Bird) != (views == "bird")) continue;
            o.view = mode;
            out += (first ? "" : ",\n ") + nt::toJson(nt::measureLabelQuality(o));
            first = false;
        }
        std::printf("%s]\n", out.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "navmap-label-quality: %s\n", e.what());
        return 1;
    }
    return 0;
}
