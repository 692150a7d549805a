// navmap-view: a display client for navmapd's frame stream (docs/frame-protocol.md).
// Connects with a profile, receives frames, optionally saves them as PNG, and prints frames/s,
// latency p50/p99 (source timestamp -> receipt, and render -> receipt) and drops. Each status the
// server sends before the first frame (the map still loading) is printed as `status: {...}`.

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "navmap/ipc/frame_png.h"
#include "navmap/ipc/stream_client.h"

namespace {

struct Options {
    std::string unixPath;
    std::string tcpHost;
    int tcpPort = -1;
    navmap::ipc::StreamRequest request;
    bool payloadGiven = false;
    long frames = 100;
    double duration = 0;
    std::string saveDir;
    long saveCount = -1;
    bool json = false;
};

void usage(std::FILE* f) {
    std::fputs(
        "usage: navmap-view (--unix PATH | --tcp HOST:PORT) [options]\n"
        "  --profile NAME       cluster | hud | center | a custom name (default cluster)\n"
        "  --width W --height H --view bird|snail|hud --fps F --format rgba8|rgb565\n"
        "  --payload shm|raw|zlib  (default: shm over --unix, raw over --tcp)\n"
        "  --frames N           stop after N frames (default 100, 0 = no limit)\n"
        "  --duration S         stop after S seconds\n"
        "  --save DIR           write frames as DIR/frame_<seq>.png\n"
        "  --save-count N       save at most N frames (default: all received)\n"
        "  --json               print the summary as one JSON object (status lines go to stderr)\n",
        f);
}

bool parseInt(const char* s, long lo, long hi, long* out) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) {
        return false;
    }
    *out = v;
    return true;
}

// Returns an empty string on success, else the problem.
std::string parseArgs(int argc, char** argv, Options* o) {
    o->request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    navmap::ipc::StreamProfile& p = o->request.profile;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        long n = 0;
        if (a == "--help" || a == "-h") {
            usage(stdout);
            std::exit(0);
        } else if (a == "--json") {
            o->json = true;
        } else {
            const char* v = value();
            if (v == nullptr) {
                return a + " needs a value";
            }
            if (a == "--unix") {
                o->unixPath = v;
            } else if (a == "--tcp") {
                const std::string hp = v;
                const auto colon = hp.rfind(':');
                if (colon == std::string::npos || !parseInt(hp.c_str() + colon + 1, 1, 65535, &n)) {
                    return "--tcp wants HOST:PORT";
                }
                o->tcpHost = hp.substr(0, colon);
                o->tcpPort = static_cast<int>(n);
            } else if (a == "--profile") {
                if (auto d = navmap::ipc::defaultStreamProfile(v)) {
                    p = *d;
                } else {
                    p.name = v;
                }
            } else if (a == "--width" && parseInt(v, 16, 4096, &n)) {
                p.width = static_cast<int>(n);
            } else if (a == "--height" && parseInt(v, 16, 4096, &n)) {
                p.height = static_cast<int>(n);
            } else if (a == "--fps" && parseInt(v, 1, 1000, &n)) {
                p.fps = static_cast<int>(n);
            } else if (a == "--view") {
                p.view = v;
            } else if (a == "--format") {
                const auto f = navmap::ipc::parsePixelFormat(v);
                if (!f) {
                    return "--format: rgba8 or rgb565";
                }
                p.format = *f;
            } else if (a == "--payload") {
                const std::string s = v;
                o->payloadGiven = true;
                if (s == "shm") {
                    o->request.payload = navmap::ipc::StreamPayload::Shm;
                } else if (s == "raw") {
                    o->request.payload = navmap::ipc::StreamPayload::Raw;
                } else if (s == "zlib") {
                    o->request.payload = navmap::ipc::StreamPayload::Zlib;
                } else {
                    return "--payload: shm, raw or zlib";
                }
            } else if (a == "--frames" && parseInt(v, 0, 1L << 40, &n)) {
                o->frames = n;
            } else if (a == "--duration") {
                o->duration = std::atof(v);
            } else if (a == "--save") {
                o->saveDir = v;
            } else if (a == "--save-count" && parseInt(v, 0, 1L << 40, &n)) {
                o->saveCount = n;
            } else {
                return "bad option or value: " + a + " " + v;
            }
        }
    }
    if (o->unixPath.empty() == (o->tcpPort < 0)) {
        return "give exactly one of --unix PATH and --tcp HOST:PORT";
    }
    if (!o->payloadGiven) {
        o->request.payload = o->unixPath.empty() ? navmap::ipc::StreamPayload::Raw : navmap::ipc::StreamPayload::Shm;
    }
    return {};
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) {
        return 0;
    }
    std::sort(v.begin(), v.end());
    const auto idx = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(idx, v.size() - 1)];
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const std::string err = parseArgs(argc, argv, &o); !err.empty()) {
        std::fprintf(stderr, "navmap-view: %s\n", err.c_str());
        usage(stderr);
        return 2;
    }
    // SIGINT/SIGTERM are blocked and polled between frames (no handler, no global flag).
    sigset_t stopSignals;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGINT);
    sigaddset(&stopSignals, SIGTERM);
    sigprocmask(SIG_BLOCK, &stopSignals, nullptr);

    auto connected = o.unixPath.empty() ? navmap::ipc::StreamClient::connectTcp(o.tcpHost, o.tcpPort, o.request)
                                        : navmap::ipc::StreamClient::connectUnix(o.unixPath, o.request);
    if (!connected) {
        std::fprintf(stderr, "navmap-view: %s\n", connected.error().message.c_str());
        return 1;
    }
    auto& client = *connected.value();
    if (!o.saveDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.saveDir, ec);
        if (ec) {
            std::fprintf(stderr, "navmap-view: mkdir(%s): %s\n", o.saveDir.c_str(), ec.message().c_str());
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
    std::FILE* statusOut = o.json ? stderr : stdout;
    client.setStatusHandler([statusOut](const std::string& text) {
        std::fprintf(statusOut, "status: %s\n", text.c_str());
        std::fflush(statusOut);
    });
    navmap::ipc::ReceivedFrame frame;
    std::vector<double> sourceLatencyMs;
    std::vector<double> renderLatencyMs;
    long received = 0;
    long saved = 0;
    std::uint64_t dropped = 0;
    std::string endReason = "done";
    int rc = 0;
    const auto start = std::chrono::steady_clock::now();
    auto firstFrame = start;
    auto lastFrame = start;
    for (;;) {
        const timespec zero{0, 0};
        if (sigtimedwait(&stopSignals, nullptr, &zero) > 0) {
            endReason = "interrupted";
            break;
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if ((o.frames > 0 && received >= o.frames) || (o.duration > 0 && elapsed >= o.duration)) {
            break;
        }
        auto r = client.next(frame, std::chrono::milliseconds(200));
        if (!r) {
            std::fprintf(stderr, "navmap-view: %s\n", r.error().message.c_str());
            endReason = "error";
            rc = 1;
            break;
        }
        if (!r.value()) {
            continue;
        }
        lastFrame = std::chrono::steady_clock::now();
        if (received == 0) {
            firstFrame = lastFrame;
        }
        ++received;
        dropped = frame.header.dropped;
        if (frame.header.sourceTimeNs != 0) {
            sourceLatencyMs.push_back(static_cast<double>(frame.receiveTimeNs - frame.header.sourceTimeNs) / 1e6);
        }
        renderLatencyMs.push_back(static_cast<double>(frame.receiveTimeNs - frame.header.renderTimeNs) / 1e6);
        if (!o.saveDir.empty() && (o.saveCount < 0 || saved < o.saveCount)) {
            char name[64];
            std::snprintf(name, sizeof(name), "frame_%06llu.png", static_cast<unsigned long long>(frame.header.sequence));
            const std::string path = (std::filesystem::path(o.saveDir) / name).string();
            if (auto s = navmap::ipc::writeFramePng(path, frame.header, frame.pixels.data()); !s) {
                std::fprintf(stderr, "navmap-view: %s\n", s.message().c_str());
                endReason = "error";
                rc = 1;
                break;
            }
            ++saved;
        }
    }
    const double span = std::chrono::duration<double>(lastFrame - firstFrame).count();
    const double fps = received > 1 && span > 0 ? static_cast<double>(received - 1) / span : 0;
    const double sP50 = percentile(sourceLatencyMs, 0.5), sP99 = percentile(sourceLatencyMs, 0.99);
    const double rP50 = percentile(renderLatencyMs, 0.5), rP99 = percentile(renderLatencyMs, 0.99);
    if (o.json) {
        std::printf("{\"frames\":%ld,\"fps\":%.2f,\"dropped\":%llu,\"lost_locally\":%llu,\"saved\":%ld,\"statuses\":%llu,"
                    "\"source_latency_ms\":{\"samples\":%zu,\"p50\":%.3f,\"p99\":%.3f},"
                    "\"render_latency_ms\":{\"p50\":%.3f,\"p99\":%.3f},\"end\":\"%s\"}\n",
                    received, fps, static_cast<unsigned long long>(dropped),
                    static_cast<unsigned long long>(client.stats().lostLocally), saved,
                    static_cast<unsigned long long>(client.stats().statuses), sourceLatencyMs.size(), sP50,
                    sP99, rP50, rP99, endReason.c_str());
    } else {
        std::printf("frames %ld  fps %.2f  dropped %llu  saved %ld\n", received, fps,
                    static_cast<unsigned long long>(dropped), saved);
        if (sourceLatencyMs.empty()) {
            std::printf("latency source->receipt: no source timestamps in the stream\n");
        } else {
            std::printf("latency source->receipt ms: p50 %.3f  p99 %.3f  (%zu frames)\n", sP50, sP99,
                        sourceLatencyMs.size());
        }
        std::printf("latency render->receipt ms: p50 %.3f  p99 %.3f\n", rP50, rP99);
    }
    return rc;
}
