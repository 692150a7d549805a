// SPDX-License-Identifier: Apache-2.0
// navmap-wayland: shows navmapd's frame stream of one profile on a Wayland surface
// (docs/wayland.md). ivi-shell (ivi_application, --ivi-id) where the compositor offers it, else
// xdg-shell; wl_shm buffers filled from the shared-memory ring with one copy; the window's size
// follows the compositor's configure events and is asked of navmapd (a refused size: the
// profile's frames scaled to fit, said once); navmapd gone: the last frame stays while the
// client reconnects with backoff. Exit status: 0 stopped (signal, --duration, --frames, the
// window closed), 1 a Wayland failure (no compositor, compositor gone, protocol error), 2 usage.

#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>

#include "buffer_source.h"
#include "frame_feed.h"
#include "navmap/cli/cli.h"
#include "navmap/ipc/client/zlib_inflater.h"
#include "shm_buffer_source.h"
#include "wayland_window.h"

namespace {

using navmap::ipc::wayland::ShellKind;

struct Options {
    navmap::ipc::ReconnectOptions stream;
    navmap::ipc::wayland::WindowOptions window;
    bool negotiate = true;
    double duration_s = 0;
    long frames = 0;
};

std::optional<int> usage(const std::string& why) {
    std::fprintf(stderr, "navmap-wayland: %s\nRun with --help for more information.\n", why.c_str());
    return navmap::cli::kExitUsage;
}

// Parses the command line into `o`; nullopt to go on, else the exit status.
std::optional<int> parseArgs(int argc, char** argv, Options* o) {
    using navmap::cli::finiteIn;
    using navmap::cli::integerIn;
    CLI::App app{"navmap-wayland: show navmapd's frames of one profile on a Wayland surface (ivi-shell or xdg-shell)"};
    navmap::cli::setUp(app, "navmap-wayland");
    std::string profile = "cluster", view, format, payload, tcp, shell = "auto";
    std::optional<int> width, height, fps;
    bool fixed_size = false;
    auto* unix = app.add_option("--unix", o->stream.unix_path, "navmapd's frame socket (payload shm by default)");
    auto* tcp_opt = app.add_option("--tcp", tcp, "HOST:PORT of navmapd's TCP frame server (payload raw by default)");
    unix->excludes(tcp_opt);
    app.add_option("--profile", profile, "cluster | hud | center | a profile the daemon renders")
        ->capture_default_str();
    app.add_option("--width", width, "frame width (default: the profile's)")->check(integerIn(16, 4096));
    app.add_option("--height", height, "frame height (default: the profile's)")->check(integerIn(16, 4096));
    app.add_option("--view", view, "bird | snail | hud (default: the profile's)")
        ->check(CLI::IsMember({"bird", "snail", "hud"}));
    app.add_option("--fps", fps, "most frames per second wanted (default: the profile's)")->check(integerIn(0, 1000));
    app.add_option("--format", format, "rgba8 | rgb565 (default rgba8)")->check(CLI::IsMember({"rgba8", "rgb565"}));
    app.add_option("--payload", payload, "shm | raw | zlib (default: shm over --unix, raw over --tcp)")
        ->check(CLI::IsMember({"shm", "raw", "zlib"}));
    bool dmabuf = false;
    app.add_flag("--dmabuf", dmabuf,
                 "ask navmapd for dma-buf frames first, falling back to shm (wl_shm) with one log line "
                 "naming why (needs --unix)");
    app.add_option("--shell", shell, "auto (ivi-shell where offered, else xdg-shell) | ivi | xdg")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "ivi", "xdg"}));
    app.add_option("--ivi-id", o->window.ivi_id, "the surface's ivi_id under ivi-shell")
        ->capture_default_str()
        ->check(integerIn(0, 4294967295LL));
    app.add_option("--title", o->window.title, "the window title under xdg-shell")->capture_default_str();
    app.add_flag("--fullscreen", o->window.fullscreen, "xdg-shell: ask the compositor for the whole output");
    app.add_flag("--fixed-size", fixed_size,
                 "never ask navmapd for the window's size: scale the profile's frames to fit");
    app.add_option("--duration", o->duration_s, "stop after S seconds, 0 = no limit")->check(finiteIn(0.0, 1e7));
    app.add_option("--frames", o->frames, "stop after N frames shown, 0 = no limit")->check(integerIn(0, 1LL << 40));
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) {
        return exit_status;
    }
    if (o->stream.unix_path.empty() == tcp.empty()) {
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
        o->stream.tcp_host = tcp.substr(0, colon);
        o->stream.tcp_port = static_cast<int>(port);
    }
    navmap::ipc::StreamProfile& p = o->stream.request.profile;
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
    using navmap::ipc::StreamPayload;
    if (payload.empty()) {
        o->stream.request.payload = o->stream.unix_path.empty() ? StreamPayload::Raw : StreamPayload::Shm;
    } else {
        o->stream.request.payload = payload == "shm"   ? StreamPayload::Shm
                                    : payload == "raw" ? StreamPayload::Raw
                                                       : StreamPayload::Zlib;
    }
    if (o->stream.request.payload == StreamPayload::Shm && o->stream.unix_path.empty()) {
        return usage("--payload shm needs --unix (shared memory is local)");
    }
    if (dmabuf) {
        if (o->stream.unix_path.empty() || (!payload.empty() && payload != "shm")) {
            return usage("--dmabuf needs --unix and payload shm to fall back to (dma-bufs are local)");
        }
        o->stream.request.payload = StreamPayload::Dmabuf;
        o->stream.request.dmabuf_fallback_shm = true;
    }
    o->stream.inflate = navmap::ipc::zlibInflater();
    o->window.shell = shell == "ivi" ? ShellKind::Ivi : shell == "xdg" ? ShellKind::Xdg : ShellKind::Auto;
    o->window.width = p.width;
    o->window.height = p.height;
    o->negotiate = !fixed_size;
    return std::nullopt;
}

// The loop: Wayland events, frames, signals. Returns the exit status.
class Display {
public:
    Display(const Options& o, navmap::ipc::wayland::WaylandWindow& window, navmap::ipc::wayland::BufferSource& buffers,
            int signal_fd)
        : m_o(o),
          m_window(window),
          m_buffers(buffers),
          m_feed(o.stream, o.negotiate, stderr),
          m_signal_fd(signal_fd),
          m_width(o.window.width),
          m_height(o.window.height) {}

    int run();

private:
    bool applyConfigure();
    bool show(const navmap::ipc::wayland::FeedFrame& frame);
    int fail(const std::string& why) {
        std::fprintf(stderr, "navmap-wayland: %s\n", why.c_str());
        return navmap::cli::kExitFailure;
    }

    const Options& m_o;
    navmap::ipc::wayland::WaylandWindow& m_window;
    navmap::ipc::wayland::BufferSource& m_buffers;
    navmap::ipc::wayland::FrameFeed m_feed;
    int m_signal_fd;
    int m_width;
    int m_height;
    bool m_mapped = false;  ///< a buffer was committed
    bool m_logged_scaling = false;
    long m_shown = 0;
    long m_skipped = 0;
};

// Takes the compositor's newest size; true when the surface needs a commit (an xdg ack).
bool Display::applyConfigure() {
    int w = 0, h = 0;
    if (!m_window.takeConfigure(&w, &h)) return false;
    if (w > 0 && h > 0 && (w != m_width || h != m_height)) {
        std::fprintf(stderr, "navmap-wayland: the compositor sized the surface %dx%d\n", w, h);
        m_width = w;
        m_height = h;
        m_logged_scaling = false;
    }
    m_feed.wantSize(m_width, m_height);
    return true;
}

bool Display::show(const navmap::ipc::wayland::FeedFrame& frame) {
    navmap::ipc::wayland::DisplayFrame d;
    d.pixels = {frame.pixels, static_cast<int>(frame.header.width), static_cast<int>(frame.header.height),
                frame.header.stride, frame.header.format};
    d.sequence = frame.header.sequence;
    if (!m_buffers.attach(m_window.surface(), d, m_width, m_height)) {
        m_feed.release();
        ++m_skipped;
        return m_buffers.lastError().empty();
    }
    m_feed.release();  // copied: the ring slot goes back to navmapd at once
    m_window.commit();
    m_mapped = true;
    ++m_shown;
    if (m_buffers.lastPlacement().scaled && !m_logged_scaling) {
        const auto p = m_buffers.lastPlacement();
        std::fprintf(stderr, "navmap-wayland: %dx%d frames scaled to %dx%d at (%d, %d) in the %dx%d surface\n",
                     d.pixels.width, d.pixels.height, p.width, p.height, p.x, p.y, m_width, m_height);
        m_logged_scaling = true;
    }
    return true;
}

int Display::run() {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    for (;;) {
        if (m_o.duration_s > 0 && std::chrono::duration<double>(Clock::now() - start).count() >= m_o.duration_s) break;
        if (m_o.frames > 0 && m_shown >= m_o.frames) break;
        if (m_window.closeRequested()) break;
        const bool configured = applyConfigure();
        if (m_window.canDraw() && !m_mapped) {
            // Black until the first frame, so the surface is on screen and placed.
            if (!m_buffers.attachBlank(m_window.surface(), m_width, m_height)) return fail(m_buffers.lastError());
            m_window.commit();
            m_mapped = true;
        } else if (configured && m_mapped) {
            m_window.commit();  // acknowledges the size; the next frame fills it
        }
        if (auto s = m_window.prepare(); !s) return fail(s.message());
        const int stream_fd = m_feed.fd();
        pollfd fds[3] = {{m_window.fd(), POLLIN, 0}, {m_signal_fd, POLLIN, 0}, {stream_fd, POLLIN, 0}};
        const int n = ::poll(fds, stream_fd >= 0 ? 3 : 2, stream_fd >= 0 ? 200 : 50);
        if (n < 0 && errno != EINTR) {
            static_cast<void>(m_window.dispatch(false));
            return fail(std::string("poll(Wayland display): ") + std::strerror(errno));
        }
        if (auto s = m_window.dispatch(n > 0 && (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0); !s) {
            return fail(s.message());
        }
        if (n > 0 && (fds[1].revents & POLLIN) != 0) break;  // SIGINT, SIGTERM
        const bool stream_ready = stream_fd >= 0 && n > 0 && fds[2].revents != 0;
        if (stream_fd >= 0 && !stream_ready) continue;
        navmap::ipc::wayland::FeedFrame frame;
        if (!m_feed.next(frame, std::chrono::milliseconds(stream_fd >= 0 ? 0 : 50))) continue;
        if (!m_window.canDraw()) {
            m_feed.release();
            continue;
        }
        if (!show(frame)) return fail(m_buffers.lastError());
    }
    std::fprintf(stderr, "navmap-wayland: %ld frames shown, %ld skipped (every buffer still on screen)\n", m_shown,
                 m_skipped);
    return navmap::cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const auto exit_status = parseArgs(argc, argv, &o)) {
        return *exit_status;
    }
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    sigprocmask(SIG_BLOCK, &stop_signals, nullptr);
    const int signal_fd = signalfd(-1, &stop_signals, SFD_CLOEXEC);
    signal(SIGPIPE, SIG_IGN);  // a compositor or navmapd gone is an error return, not a signal

    auto window = navmap::ipc::wayland::WaylandWindow::open(o.window);
    if (!window) {
        std::fprintf(stderr, "navmap-wayland: %s\n", window.error().message.c_str());
        return navmap::cli::kExitFailure;
    }
    auto& w = *window.value();
    navmap::ipc::wayland::ShmBufferSource buffers(w.shm(), w.shmFormats());
    if (w.shellName() == std::string("ivi-shell")) {
        std::fprintf(stderr, "navmap-wayland: ivi-shell, ivi_id %u; %s buffers, %s frames as %s\n", o.window.ivi_id,
                     buffers.name(), navmap::ipc::pixelFormatName(o.stream.request.profile.format),
                     navmap::ipc::wayland::shmFormatName(buffers.formatFor(o.stream.request.profile.format)));
    } else {
        std::fprintf(stderr, "navmap-wayland: xdg-shell; %s buffers, %s frames as %s\n", buffers.name(),
                     navmap::ipc::pixelFormatName(o.stream.request.profile.format),
                     navmap::ipc::wayland::shmFormatName(buffers.formatFor(o.stream.request.profile.format)));
    }
    Display display(o, w, buffers, signal_fd);
    const int rc = display.run();
    close(signal_fd);
    return rc;
}
