// navmapd: the navigation-map renderer daemon. In this version the main job renders the
// embedded default scene (the SRTM heightfield of Andorra) along a fly-over and writes the
// frames as PNG; vehicle input, tiles and frame streaming are added by later parts.

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "navmap/map/dem.h"
#include "navmap/render/renderer.h"
#include "navmap/render/terrain_scene.h"

namespace {

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

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"navmapd - headless 3D navigation-map renderer"};
    std::string dem_path = NAVMAP_DEFAULT_DEM;
    std::string out_dir = "out/frames";
    std::string platform_name = "auto";
    int frames = 24;
    int width = 1280, height = 480, msaa = -1;
    bool noop = false;
    app.add_option("--dem", dem_path, "SRTM .hgt tile")->capture_default_str();
    app.add_option("--out", out_dir, "directory for the PNG frames")->capture_default_str();
    app.add_option("--frames", frames, "frames of the fly-over to render")->capture_default_str()->check(CLI::Range(1, 100000));
    app.add_option("--width", width, "frame width")->capture_default_str()->check(CLI::Range(16, 8192));
    app.add_option("--height", height, "frame height")->capture_default_str()->check(CLI::Range(16, 8192));
    app.add_option("--msaa", msaa, "MSAA samples (0 = off, -1 = auto: off on software rasterizers)")
        ->capture_default_str()->check(CLI::Range(-1, 16));
    app.add_option("--egl-platform", platform_name, "auto | surfaceless | device (env NAVMAP_EGL_PLATFORM)")
        ->capture_default_str()->check(CLI::IsMember({"auto", "surfaceless", "device"}));
    app.add_flag("--noop", noop, "use the no-op renderer (no GL; blank frames)");
    CLI11_PARSE(app, argc, argv);

    using navmap::render::Renderer;
    try {
        const auto t_load = std::chrono::steady_clock::now();
        navmap::render::TerrainScene scene = navmap::render::loadTerrainScene(dem_path);
        logf(kInfo, "terrain: %s, %zu vertices, %zu triangles, heights %.0f..%.0f m, %zu voids filled (%.0f ms)",
             dem_path.c_str(), scene.mesh.vertices.size(), scene.mesh.indices.size() / 3, scene.mesh.min_height,
             scene.mesh.max_height, scene.voids_filled, msSince(t_load));

        navmap::render::RendererOptions options;
        options.platform = *navmap::render::parsePlatform(platform_name);
        options.width = width;
        options.height = height;
        options.msaa_samples = msaa;
        auto renderer = noop ? Renderer::createNoop(options) : Renderer::create(options);
        const auto& dev = renderer->device();
        logf(kInfo, "renderer: %s on %s platform, %s, %s, GLES %d.%d context, MSAA %dx", dev.backend.c_str(),
             dev.platform.c_str(), dev.renderer.c_str(), dev.version.c_str(), dev.gles_major, dev.gles_minor,
             dev.msaa_samples);
        renderer->setTerrain(scene.mesh);

        std::filesystem::create_directories(out_dir);
        std::vector<double> frame_ms;
        std::size_t written = 0;
        auto save = [&](const navmap::render::Frame& frame) {
            char name[64];
            std::snprintf(name, sizeof name, "frame_%04llu.png", static_cast<unsigned long long>(frame.sequence));
            std::string error;
            if (!navmap::render::writePng(std::filesystem::path(out_dir) / name, frame.image, &error)) {
                logf(kErr, "cannot write frame: %s", error.c_str());
                return;
            }
            ++written;
        };
        for (int i = 0; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            renderer->render(navmap::render::andorraFlyoverCamera(scene.projection, static_cast<double>(i) / frames));
            auto done = renderer->readAsync(static_cast<std::uint64_t>(i));
            frame_ms.push_back(msSince(t0));
            if (done) save(*done);
            if ((i + 1) % 8 == 0 || i + 1 == frames) logf(kInfo, "rendered %d/%d frames", i + 1, frames);
        }
        for (const auto& f : renderer->drainReadbacks()) save(f);
        std::sort(frame_ms.begin(), frame_ms.end());
        logf(kInfo, "frame time (render + readback submit): median %.1f ms, max %.1f ms",
             frame_ms[frame_ms.size() / 2], frame_ms.back());
        if (written != static_cast<std::size_t>(frames)) {
            logf(kWarning, "%zu of %d frames written", written, frames);
            return 1;
        }
        std::printf("%zu frames (%dx%d) written to %s/frame_0000.png ... frame_%04d.png\n", written, width, height,
                    std::filesystem::absolute(out_dir).lexically_normal().c_str(), frames - 1);
        return 0;
    } catch (const std::exception& e) {
        logf(kErr, "%s", e.what());
        return 1;
    }
}
