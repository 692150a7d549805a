// SPDX-License-Identifier: Apache-2.0
// navmap-view: a display client for navmapd's frame stream (docs/frame-protocol.md).
// Connects with a profile, receives frames, optionally saves them as PNG, and prints frames/s,
// latency p50/p99 (source timestamp -> receipt, and render -> receipt) and drops. Each status the
// server sends before the first frame (the map still loading) is printed as `status: {...}`.
// Each frame's validity is counted for the summary; with --meta each frame's metadata block (pose,
// next manoeuvre, remaining route, street, speed limit) is printed as `meta: {...}`.
// Exit status: 0 ok, 1 the stream failed (refused, closed, a PNG not written), 2 usage
// (docs/tools.md).

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "navmap/cli/cli.h"
#include "navmap/common/percentile.h"
#include "navmap/ipc/client/frame_png.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/client/zlib_inflater.h"

namespace {

struct Options {
    std::string unix_path;
    std::string tcp_host;
    int tcp_port = -1;
    navmap::ipc::StreamRequest request;
    long frames = 100;
    double duration = 0;
    std::string save_dir;
    long save_count = -1;
    bool json = false;
    bool zero_copy = false;
    bool meta = false;
};

// Frames by validity (a frame both stale and off route counts in both).
struct ValidityCounts {
    long fresh = 0, stale_pose = 0, degraded = 0, off_route = 0, unknown = 0;
    void add(const navmap::ipc::FrameValidity& v) {
        fresh += v.fresh() ? 1 : 0;
        unknown += v.known() ? 0 : 1;
        stale_pose += (v.flags & navmap::ipc::kValidityStalePose) != 0 ? 1 : 0;
        degraded += (v.flags & navmap::ipc::kValidityDegraded) != 0 ? 1 : 0;
        off_route += (v.flags & navmap::ipc::kValidityOffRoute) != 0 ? 1 : 0;
    }
};

std::string lanesText(const navmap::ipc::FrameMeta& m) {
    if (!m.lanes_known) {
        return "unknown";
    }
    std::string out;
    for (const std::uint8_t lane : m.lanes) {
        char b[8];
        std::snprintf(b, sizeof(b), "%s%02x", out.empty() ? "" : ",", lane);
        out += b;
    }
    return out;
}

// One frame's validity and metadata block as a JSON object (docs/frame-protocol.md names).
std::string metaJson(const navmap::ipc::FrameHeader& h, const std::optional<navmap::ipc::FrameMeta>& meta) {
    nlohmann::json j;
    j["seq"] = h.sequence;
    j["validity"] = navmap::ipc::validityText(h.validity);
    if (h.validity.known()) {
        j["pose_age_ms"] = h.validity.pose_age_ms == navmap::ipc::kPoseAgeNone ? nlohmann::json(nullptr)
                                                                               : nlohmann::json(h.validity.pose_age_ms);
        j["degraded"] = navmap::ipc::degradedText(h.validity.degraded);
    }
    if (!meta) {
        j["meta"] = nullptr;  // the server sent no block with this frame
        return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    }
    const auto& m = *meta;
    j["pose"] = m.has_pose ? nlohmann::json{{"lat", m.lat_deg},
                                            {"lon", m.lon_deg},
                                            {"heading", m.heading_deg},
                                            {"time_ns", m.pose_time_ns}}
                           : nlohmann::json(nullptr);
    j["next"] = m.has_next ? nlohmann::json{{"type", navmap::ipc::metaManeuverName(m.next_type)},
                                            {"exit", m.next_exit},
                                            {"distance_m", m.next_distance_m},
                                            {"street", m.next_street},
                                            {"lanes", lanesText(m)}}
                           : nlohmann::json(nullptr);
    j["remaining"] =
        m.has_remaining ? nlohmann::json{{"m", m.remaining_m}, {"s", m.remaining_s}} : nlohmann::json(nullptr);
    j["street"] = m.current_street;
    j["speed_limit_kmh"] = m.speed_limit_kmh == 0 ? nlohmann::json("unknown") : nlohmann::json(m.speed_limit_kmh);
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Parses the command line into `o`; nullopt to go on, else the exit status.
std::optional<int> parseArgs(int argc, char** argv, Options* o) {
    using navmap::cli::finiteIn;
    using navmap::cli::integerIn;
    CLI::App app{"navmap-view: receive navmapd's frames as a display would, save PNGs, print fps, latency and drops"};
    navmap::cli::setUp(app, "navmap-view");
    std::string profile = "cluster", view, format, payload, tcp;
    std::optional<int> width, height, fps;
    auto* unix = app.add_option("--unix", o->unix_path, "navmapd's frame socket (payload shm by default)");
    auto* tcp_opt = app.add_option("--tcp", tcp, "HOST:PORT of navmapd's TCP frame server (payload raw by default)");
    unix->excludes(tcp_opt);
    app.add_option("--profile", profile, "cluster | hud | center | a profile the daemon renders")
        ->capture_default_str();
    app.add_option("--width", width, "frame width (default: the profile's)")->check(integerIn(16, 4096));
    app.add_option("--height", height, "frame height (default: the profile's)")->check(integerIn(16, 4096));
    app.add_option("--view", view, "bird | snail | hud (default: the profile's)")
        ->check(CLI::IsMember({"bird", "snail", "hud"}));
    app.add_option("--fps", fps, "most frames per second wanted, 0 = every frame (default: the profile's)")
        ->check(integerIn(0, 1000));
    app.add_option("--format", format, "rgba8 | rgb565 (default rgba8)")->check(CLI::IsMember({"rgba8", "rgb565"}));
    app.add_option("--payload", payload, "shm | raw | zlib (default: shm over --unix, raw over --tcp)")
        ->check(CLI::IsMember({"shm", "raw", "zlib"}));
    app.add_option("--frames", o->frames, "stop after N frames, 0 = no limit")
        ->capture_default_str()
        ->check(integerIn(0, 1LL << 40));
    app.add_option("--duration", o->duration, "stop after S seconds, 0 = no limit")->check(finiteIn(0.0, 1e7));
    app.add_option("--save", o->save_dir, "write frames as DIR/frame_<seq>.png");
    app.add_option("--save-count", o->save_count, "save at most N frames (default: all received)")
        ->check(integerIn(0, 1LL << 40));
    app.add_flag("--zero-copy", o->zero_copy,
                 "payload shm: use each frame in place in the ring until the next (no copy)");
    app.add_flag("--meta", o->meta,
                 "ask for each frame's metadata block and print it as one `meta: {...}` line per frame");
    app.add_flag("--json", o->json, "print the summary as one JSON object (status lines go to stderr)");
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) {
        return exit_status;
    }
    const auto usage = [](const std::string& why) {
        std::fprintf(stderr, "navmap-view: %s\nRun with --help for more information.\n", why.c_str());
        return navmap::cli::kExitUsage;
    };
    if (o->unix_path.empty() == tcp.empty()) {
        return usage("give exactly one of --unix PATH and --tcp HOST:PORT");
    }
    if (!tcp.empty()) {
        const auto colon = tcp.rfind(':');
        char* end = nullptr;
        const long port = colon == std::string::npos ? 0 : std::strtol(tcp.c_str() + colon + 1, &end, 10);
        if (colon == std::string::npos || colon == 0 || end == tcp.c_str() + colon + 1 || *end != '\0' || port < 1 ||
            port > 65535) {
            return usage("--tcp: '" + tcp + "' is not HOST:PORT with a port in [1, 65535]");
        }
        o->tcp_host = tcp.substr(0, colon);
        o->tcp_port = static_cast<int>(port);
    }
    navmap::ipc::StreamProfile& p = o->request.profile;
    if (auto d = navmap::ipc::defaultStreamProfile(profile)) {
        p = *d;
    } else {
        p.name = profile;
    }
    if (width) p.width = *width;
    if (height) p.height = *height;
    if (fps) p.fps = *fps;
    if (!view.empty()) p.view = view;
    if (!format.empty()) p.format = *navmap::ipc::parsePixelFormat(format);
    if (payload.empty()) {
        o->request.payload = o->unix_path.empty() ? navmap::ipc::StreamPayload::Raw : navmap::ipc::StreamPayload::Shm;
    } else {
        o->request.payload = payload == "shm"   ? navmap::ipc::StreamPayload::Shm
                             : payload == "raw" ? navmap::ipc::StreamPayload::Raw
                                                : navmap::ipc::StreamPayload::Zlib;
    }
    if (o->zero_copy && o->request.payload != navmap::ipc::StreamPayload::Shm) {
        return usage("--zero-copy needs payload shm (--unix)");
    }
    o->request.hold = o->zero_copy;
    o->request.meta = o->meta;
    return std::nullopt;
}

using navmap::percentile;

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const auto exit_status = parseArgs(argc, argv, &o)) {
        return *exit_status;
    }
    // SIGINT/SIGTERM are blocked and polled between frames (no handler, no global flag).
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    sigprocmask(SIG_BLOCK, &stop_signals, nullptr);

    const auto timeout = std::chrono::seconds(5);
    auto connected = o.unix_path.empty() ? navmap::ipc::StreamClient::connectTcp(o.tcp_host, o.tcp_port, o.request,
                                                                                 timeout, navmap::ipc::zlibInflater())
                                         : navmap::ipc::StreamClient::connectUnix(o.unix_path, o.request, timeout,
                                                                                  navmap::ipc::zlibInflater());
    if (!connected) {
        std::fprintf(stderr, "navmap-view: %s\n", connected.error().message.c_str());
        return 1;
    }
    auto& client = *connected.value();
    if (!o.save_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.save_dir, ec);
        if (ec) {
            std::fprintf(stderr, "navmap-view: mkdir(%s): %s\n", o.save_dir.c_str(), ec.message().c_str());
            return 1;
        }
    }
    const auto& prof = client.profile();
    if (!o.json) {
        std::printf("navmap-view: %s %dx%d %s %s, payload %s\n", prof.name.c_str(), prof.width, prof.height,
                    prof.view.c_str(), navmap::ipc::pixelFormatName(prof.format),
                    navmap::ipc::streamPayloadName(client.payload()));
    }
    // Statuses arrive while the server holds frames back (docs/frame-protocol.md); with --json,
    // stdout stays one JSON object and they go to stderr.
    std::FILE* status_out = o.json ? stderr : stdout;
    client.setStatusHandler([status_out](const std::string& text) {
        std::fprintf(status_out, "status: %s\n", text.c_str());
        std::fflush(status_out);
    });
    navmap::ipc::ReceivedFrame frame;
    navmap::ipc::HeldFrame held;
    std::vector<double> source_latency_ms;
    std::vector<double> render_latency_ms;
    long received = 0;
    long saved = 0;
    std::uint64_t dropped = 0;
    std::string end_reason = "done";
    int rc = 0;
    const auto start = std::chrono::steady_clock::now();
    auto first_frame = start;
    auto last_frame = start;
    double longest_gap_ms = 0;  // the longest wait between two frames: a stall shows here
    ValidityCounts validity;
    for (;;) {
        const timespec zero{0, 0};
        if (sigtimedwait(&stop_signals, nullptr, &zero) > 0) {
            end_reason = "interrupted";
            break;
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if ((o.frames > 0 && received >= o.frames) || (o.duration > 0 && elapsed >= o.duration)) {
            break;
        }
        auto r = o.zero_copy ? client.nextHeld(held, std::chrono::milliseconds(200))
                             : client.next(frame, std::chrono::milliseconds(200));
        if (!r) {
            std::fprintf(stderr, "navmap-view: %s\n", r.error().message.c_str());
            end_reason = "error";
            rc = 1;
            break;
        }
        if (!r.value()) {
            continue;
        }
        // In place (--zero-copy) or the client's copy: the same header and pixels either way.
        const navmap::ipc::FrameHeader& header = o.zero_copy ? held.header : frame.header;
        const std::uint8_t* pixels = o.zero_copy ? held.pixels : frame.pixels.data();
        const std::int64_t receive_time_ns = o.zero_copy ? held.receive_time_ns : frame.receive_time_ns;
        validity.add(header.validity);
        if (o.meta) {
            std::fprintf(status_out, "meta: %s\n", metaJson(header, o.zero_copy ? held.meta : frame.meta).c_str());
        }
        const auto now = std::chrono::steady_clock::now();
        if (received > 0) {
            longest_gap_ms =
                std::max(longest_gap_ms, std::chrono::duration<double, std::milli>(now - last_frame).count());
        }
        last_frame = now;
        if (received == 0) {
            first_frame = last_frame;
        }
        ++received;
        dropped = header.dropped;
        if (header.source_time_ns != 0) {
            source_latency_ms.push_back(static_cast<double>(receive_time_ns - header.source_time_ns) / 1e6);
        }
        render_latency_ms.push_back(static_cast<double>(receive_time_ns - header.render_time_ns) / 1e6);
        if (!o.save_dir.empty() && (o.save_count < 0 || saved < o.save_count)) {
            char name[64];
            std::snprintf(name, sizeof(name), "frame_%06llu.png", static_cast<unsigned long long>(header.sequence));
            const std::string path = (std::filesystem::path(o.save_dir) / name).string();
            if (auto s = navmap::ipc::writeFramePng(path, header, pixels); !s) {
                std::fprintf(stderr, "navmap-view: %s\n", s.message().c_str());
                end_reason = "error";
                rc = 1;
                break;
            }
            ++saved;
        }
    }
    const double span = std::chrono::duration<double>(last_frame - first_frame).count();
    const double fps = received > 1 && span > 0 ? static_cast<double>(received - 1) / span : 0;
    const double s_p50 = percentile(source_latency_ms, 0.5), s_p99 = percentile(source_latency_ms, 0.99);
    const double r_p50 = percentile(render_latency_ms, 0.5), r_p99 = percentile(render_latency_ms, 0.99);
    if (o.json) {
        std::printf(
            "{\"frames\":%ld,\"fps\":%.2f,\"dropped\":%llu,\"lost_locally\":%llu,\"saved\":%ld,\"statuses\":%llu,"
            "\"source_latency_ms\":{\"samples\":%zu,\"p50\":%.3f,\"p99\":%.3f},"
            "\"render_latency_ms\":{\"p50\":%.3f,\"p99\":%.3f},\"longest_gap_ms\":%.1f,\"held_overwritten\":%llu,"
            "\"validity\":{\"fresh\":%ld,\"stale_pose\":%ld,\"degraded\":%ld,\"off_route\":%ld,\"unknown\":%ld},"
            "\"end\":\"%s\"}\n",
            received, fps, static_cast<unsigned long long>(dropped),
            static_cast<unsigned long long>(client.stats().lost_locally), saved,
            static_cast<unsigned long long>(client.stats().statuses), source_latency_ms.size(), s_p50, s_p99, r_p50,
            r_p99, longest_gap_ms, static_cast<unsigned long long>(client.stats().held_overwritten), validity.fresh,
            validity.stale_pose, validity.degraded, validity.off_route, validity.unknown, end_reason.c_str());
    } else {
        std::printf("frames %ld  fps %.2f  dropped %llu  saved %ld  longest gap %.1f ms\n", received, fps,
                    static_cast<unsigned long long>(dropped), saved, longest_gap_ms);
        if (source_latency_ms.empty()) {
            std::printf("latency source->receipt: no source timestamps in the stream\n");
        } else {
            std::printf("latency source->receipt ms: p50 %.3f  p99 %.3f  (%zu frames)\n", s_p50, s_p99,
                        source_latency_ms.size());
        }
        std::printf("latency render->receipt ms: p50 %.3f  p99 %.3f\n", r_p50, r_p99);
        std::printf("validity: fresh %ld  stale_pose %ld  degraded %ld  off_route %ld  unknown %ld\n", validity.fresh,
                    validity.stale_pose, validity.degraded, validity.off_route, validity.unknown);
    }
    return rc;
}
