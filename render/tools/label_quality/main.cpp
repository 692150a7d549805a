// SPDX-License-Identifier: Apache-2.0
// navmap-label-quality: replays a drive through the renderer and prints the label quality
// measured on the drawn frames as JSON, one object per camera or view (docs/labels.md "Measured
// quality"): a recorded trajectory with MapLibre-convention cameras, or the route Andorra la
// Vella -> Encamp with the camera rig. Command line: cli/include/navmap/cli/cli.h (exit 0 ok,
// 1 bad input or a failed run, 2 usage).
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "label_quality.h"
#include "navmap/cli/cli.h"

int main(int argc, char** argv) {
    namespace nt = navmap::render::tools;
    namespace cli = navmap::cli;
    nt::LabelQualityOptions o;
    o.store = NAVMAP_DEFAULT_STORE;
    std::string store = o.store.string(), trajectory, views = "both", size;
    std::vector<std::string> camera_specs;
    int frames = -1;

    CLI::App app{"Replays a drive through the renderer and prints the label quality of the drawn frames as JSON."};
    cli::setUp(app, "navmap-label-quality");
    app.add_option("--store", store, "compiled tile store")->capture_default_str();
    app.add_option("--trajectory", trajectory, "replay these poses (data/drives/*-trajectory.json); needs --camera");
    app.add_option(
        "--camera", camera_specs,
        "zoom=Z,pitch=P[,bearing=B]: MapLibre GL JS camera centred on the vehicle (512-px tiles, pitch from "
        "straight down, fov 36.87); repeat for several; with a route drive the rig follows with it instead of --view");
    app.add_option("--view", views, "route drive: the camera rig's view")
        ->check(CLI::IsMember({"bird", "snail", "both"}))
        ->capture_default_str();
    app.add_option("--frames", frames, "frames measured (default: 300 on a route, every pose of a trajectory)")
        ->check(cli::integerIn(1, 1000000));
    app.add_option("--settle", o.settle_frames, "frames rendered before measuring")
        ->check(cli::integerIn(0, 1000000))
        ->capture_default_str();
    app.add_option("--dt", o.dt_s, "fixed frame time, s")->check(cli::finiteIn(0.001, 10))->capture_default_str();
    app.add_option("--size", size, "WxH of the frames (default 1280x480)");
    app.add_option("--start", o.start_m, "route: distance along the route where the drive starts, m")
        ->check(cli::finiteIn(0, 1e6))
        ->capture_default_str();
    app.add_option("--speed", o.speed_mps, "route: speed, m/s")->check(cli::finiteIn(0, 100))->capture_default_str();
    bool no_occlusion = false;
    app.add_flag("--no-occlusion", no_occlusion, "do not measure how much of each label is hidden (faster)");
    app.add_flag("--aura", o.label_aura, "draw the transparency label aura (seed 5.5.1)");
    app.add_flag("--glow", o.glow_roads, "draw glowing roads (seed 5.5.2)");
    if (const auto code = cli::parse(app, argc, argv)) return *code;

    const auto usage_error = [](const std::string& message) {
        std::fprintf(stderr, "navmap-label-quality: %s\nRun with --help for more information.\n", message.c_str());
        return cli::kExitUsage;
    };
    o.store = store;
    o.trajectory = trajectory;
    o.measure_occlusion = !no_occlusion;
    if (frames > 0) o.frames = frames;
    if (!size.empty()) {
        char x = 0, rest = 0;
        if (std::sscanf(size.c_str(), "%d%c%d%c", &o.width, &x, &o.height, &rest) != 3 || x != 'x' || o.width < 16 ||
            o.width > 8192 || o.height < 16 || o.height > 8192) {
            return usage_error("--size: '" + size + "' is not WxH with W and H integers in [16, 8192]");
        }
    }
    std::vector<navmap::render::MapLibreFollow> cameras;
    for (const auto& spec : camera_specs) {
        std::string error;
        const auto camera = nt::parseCameraSpec(spec, &error);
        if (!camera) return usage_error("--camera: " + error);
        cameras.push_back(*camera);
    }
    if (!o.trajectory.empty() && cameras.empty())
        return usage_error("--trajectory needs at least one --camera zoom=Z,pitch=P");
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
        return cli::kExitFailure;
    }
    return cli::kExitOk;
}
