// navmapd: the navigation-map renderer daemon. This version runs the main job on a compiled
// tile store with an in-process simulated drive: each tick advances the vehicle, every display
// profile in use renders its view once (camera rig -> level-of-detail tiles -> map frame), and
// the frames are read back asynchronously and recorded as PNG. Vehicle input over CAN, the
// control socket and frame streaming plug in at the marked places.

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "navmap/render/map_scene.h"
#include "navmap/render/renderer.h"
#include "profiles.h"
#include "simulated_drive.h"

namespace {

using navmap::daemon::DisplayProfile;

// Log lines carry a syslog priority prefix that journald understands (sd-daemon(3)).
template <typename... Args>
void logf(int priority, const char* fmt, Args... args) {
    std::fprintf(stderr, "<%d>navmapd: ", priority);
    std::fprintf(stderr, fmt, args...);
    std::fputc('\n', stderr);
}
constexpr int kErr = 3, kWarning = 4, kInfo = 6;

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// "42.5075,1.5218" or a built-in place name.
bool parsePlace(const std::string& text, navmap::render::GeoPoint& out) {
    struct Named {
        const char* name;
        navmap::render::GeoPoint p;
    };
    static const Named kPlaces[] = {{"andorra-la-vella", navmap::render::kAndorraLaVella},
                                    {"encamp", navmap::render::kEncamp},
                                    {"sant-julia", navmap::render::kSantJulia}};
    for (const auto& n : kPlaces) {
        if (text == n.name) {
            out = n.p;
            return true;
        }
    }
    double lat = 0, lon = 0;
    char comma = 0;
    std::istringstream in(text);
    if (in >> lat >> comma >> lon && comma == ',' && std::abs(lat) <= 90 && std::abs(lon) <= 180) {
        out = {lat, lon};
        return true;
    }
    return false;
}

struct View {
    DisplayProfile profile;
    std::unique_ptr<navmap::render::Renderer> renderer;
    std::unique_ptr<navmap::render::MapView> map_view;
    navmap::render::CameraRig rig;
    std::filesystem::path out_dir;
    std::vector<double> frame_ms;
    std::size_t written = 0;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"navmapd - headless 3D navigation-map renderer"};
    std::string store_path = NAVMAP_DEFAULT_STORE;
    std::string out_dir = "out/frames";
    std::string platform_name = "auto";
    std::string from = "andorra-la-vella", to = "encamp";
    std::vector<std::string> profile_names{"cluster", "center"};
    int frames = 60;
    double sim_step = 1.0;
    int msaa = -1;
    bool noop = false;
    app.add_option("--store", store_path, "compiled tile store (navmap-compile)")->capture_default_str();
    app.add_option("--from", from, "drive start: lat,lon or andorra-la-vella|encamp|sant-julia")->capture_default_str();
    app.add_option("--to", to, "drive destination")->capture_default_str();
    app.add_option("--profiles", profile_names, "display profiles to render: cluster hud center")
        ->capture_default_str()->delimiter(',');
    app.add_option("--out", out_dir, "directory for the recorded frames (one folder per profile)")->capture_default_str();
    app.add_option("--frames", frames, "ticks to run")->capture_default_str()->check(CLI::Range(1, 1000000));
    app.add_option("--sim-step", sim_step, "simulated seconds per tick")->capture_default_str()->check(CLI::Range(0.001, 60.0));
    app.add_option("--msaa", msaa, "MSAA samples (0 = off, -1 = auto: off on software rasterizers)")
        ->capture_default_str()->check(CLI::Range(-1, 16));
    app.add_option("--egl-platform", platform_name, "auto | surfaceless | device (env NAVMAP_EGL_PLATFORM)")
        ->capture_default_str()->check(CLI::IsMember({"auto", "surfaceless", "device"}));
    app.add_flag("--noop", noop, "use the no-op renderer (no GL; blank frames)");
    CLI11_PARSE(app, argc, argv);

    using namespace navmap;
    try {
        render::GeoPoint a{}, b{};
        if (!parsePlace(from, a)) throw std::runtime_error("--from " + from + ": expected lat,lon or a known place");
        if (!parsePlace(to, b)) throw std::runtime_error("--to " + to + ": expected lat,lon or a known place");
        const auto t_open = std::chrono::steady_clock::now();
        render::MapScene scene = render::MapScene::open(store_path);
        logf(kInfo, "store: %s, %u tiles, %zu graph nodes (%.0f ms)", store_path.c_str(), scene.store->info().tile_count,
             scene.graph.nodes.size(), msSince(t_open));

        // Vehicle input. (CAN replay / SocketCAN and the pose estimator replace this simulated drive.)
        daemon::SimulatedDrive drive(render::planDrive(scene, a.lat, a.lon, b.lat, b.lon));
        if (drive.length() <= 0.0) throw std::runtime_error("no drivable route from " + from + " to " + to);
        logf(kInfo, "simulated drive: %s -> %s, %.1f km on %zu route points", from.c_str(), to.c_str(),
             drive.length() / 1000.0, drive.drive().line.size());

        std::vector<View> views;
        const auto all = daemon::defaultProfiles();
        for (const auto& name : profile_names) {
            auto profile = daemon::findProfile(all, name);
            if (!profile) throw std::runtime_error("--profiles: unknown profile '" + name + "' (cluster, hud, center)");
            View v;
            v.profile = *profile;
            render::RendererOptions options;
            options.platform = *render::parsePlatform(platform_name);
            options.width = profile->width;
            options.height = profile->height;
            options.msaa_samples = msaa;
            v.renderer = noop ? render::Renderer::createNoop(options) : render::Renderer::create(options);
            v.map_view = std::make_unique<render::MapView>(scene.cache);
            v.rig.setMode(profile->view);
            v.rig.setOrientation(profile->orientation);
            v.out_dir = std::filesystem::path(out_dir) / name;
            std::filesystem::create_directories(v.out_dir);
            const auto& dev = v.renderer->device();
            logf(kInfo, "profile %s %dx%d %s: %s on %s, %s, MSAA %dx", name.c_str(), profile->width, profile->height,
                 profile->view == render::ViewMode::Bird ? "bird's-eye" : "snail's view", dev.backend.c_str(),
                 dev.platform.c_str(), dev.renderer.c_str(), dev.msaa_samples);
            views.push_back(std::move(v));
        }

        auto save = [&](View& v, const render::Frame& frame) {
            char name[64];
            std::snprintf(name, sizeof name, "frame_%04llu.png", static_cast<unsigned long long>(frame.sequence));
            std::string error;
            if (!render::writePng(v.out_dir / name, frame.image, &error)) {
                logf(kErr, "cannot record frame: %s", error.c_str());
                return;
            }
            ++v.written;
        };
        const auto terrain = [&](double x, double y) { return views.front().map_view->terrainHeight(x, y); };

        // Warm the tile cache for the first pose so the first frame is complete.
        for (auto& v : views) {
            const auto pose = render::poseAlong(drive.drive(), 0.0, 0.0, terrain);
            const auto cam = v.rig.update(pose, 0.0, terrain);
            v.map_view->warmUp(cam, double(v.profile.width) / v.profile.height, v.profile.height, std::chrono::seconds(20));
        }
        for (auto& p : drive.drive().geometry.points) p.z = terrain(p.x, p.y);

        for (int tick = 0; tick < frames; ++tick) {
            if (tick > 0) drive.advance(sim_step);
            const auto pose = render::poseAlong(drive.drive(), drive.measure(), drive.speed(), terrain);
            for (auto& v : views) {
                const auto t0 = std::chrono::steady_clock::now();
                render::MapFrame frame;
                frame.camera = v.rig.update(pose, tick == 0 ? 0.0 : sim_step, terrain);
                const double aspect = double(v.profile.width) / v.profile.height;
                frame.tiles = v.map_view->tilesFor(frame.camera, aspect, v.profile.height);
                frame.route = &drive.drive().geometry;
                frame.route_progress_m = drive.measure();
                frame.marker = render::MarkerState{pose.position, pose.heading_deg, false};
                v.renderer->renderMap(frame);
                auto done = v.renderer->readAsync(static_cast<std::uint64_t>(tick));
                v.frame_ms.push_back(msSince(t0));
                if (done) save(v, *done);  // frame server publishes here
            }
            if ((tick + 1) % 20 == 0 || tick + 1 == frames) {
                const auto m = scene.cache->metrics();
                logf(kInfo, "tick %d/%d: %.2f of %.2f km, %.0f km/h; tiles resident %zu (%.1f MiB), loads %llu",
                     tick + 1, frames, drive.measure() / 1000.0, drive.length() / 1000.0, drive.speed() * 3.6,
                     m.resident_tiles, m.resident_bytes / 1048576.0, static_cast<unsigned long long>(m.loads));
            }
        }
        int status = 0;
        for (auto& v : views) {
            for (const auto& f : v.renderer->drainReadbacks()) save(v, f);
            std::sort(v.frame_ms.begin(), v.frame_ms.end());
            logf(kInfo, "profile %s: frame (tiles + render + readback submit) median %.1f ms, p95 %.1f ms",
                 v.profile.name.c_str(), v.frame_ms[v.frame_ms.size() / 2],
                 v.frame_ms[std::min(v.frame_ms.size() - 1, v.frame_ms.size() * 95 / 100)]);
            if (v.written != static_cast<std::size_t>(frames)) {
                logf(kWarning, "profile %s: %zu of %d frames recorded", v.profile.name.c_str(), v.written, frames);
                status = 1;
            }
            std::printf("%s: %zu frames (%dx%d) in %s/frame_0000.png ... frame_%04d.png\n", v.profile.name.c_str(),
                        v.written, v.profile.width, v.profile.height,
                        std::filesystem::absolute(v.out_dir).lexically_normal().c_str(), frames - 1);
        }
        return status;
    } catch (const std::exception& e) {
        logf(kErr, "%s", e.what());
        return 1;
    }
}
