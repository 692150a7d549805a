// SPDX-License-Identifier: Apache-2.0
#pragma once
// WaylandWindow: navmap-wayland's connection to the compositor and its one surface
// (docs/wayland.md). The surface's role is an ivi_surface (ivi_application.surface_create with
// the configured ivi_id) where the compositor offers ivi_application, else an xdg_toplevel
// (xdg_wm_base); --shell forces one. The compositor's configure events (ivi_surface.configure,
// xdg_toplevel.configure) become the window's size; xdg's configure is acknowledged before the
// next commit. Every failure is a message that names the cause: no compositor (WAYLAND_DISPLAY),
// the compositor gone, a protocol error, a global missing. One thread: the one that runs the loop.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/net/result.h"

struct wl_display;
struct wl_registry;
struct wl_compositor;
struct wl_surface;
struct wl_shm;
struct xdg_wm_base;
struct xdg_surface;
struct xdg_toplevel;
struct ivi_application;
struct ivi_surface;

namespace navmap::ipc::wayland {

enum class ShellKind { Auto, Ivi, Xdg };

struct WindowOptions {
    ShellKind shell = ShellKind::Auto;
    std::uint32_t ivi_id = 9000;
    std::string title = "navmap";
    std::string app_id = "navmap-wayland";
    int width = 1280;  ///< the size until the compositor configures another
    int height = 480;
    bool fullscreen = false;  ///< xdg-shell: ask for the whole output (ivi-shell: the controller decides)
};

class WaylandWindow {
public:
    /// Connects to the compositor ($WAYLAND_DISPLAY, as libwayland finds it) and creates the
    /// surface with its role. The Error says what is missing.
    static Result<std::unique_ptr<WaylandWindow>> open(const WindowOptions& options);
    ~WaylandWindow();
    WaylandWindow(const WaylandWindow&) = delete;
    WaylandWindow& operator=(const WaylandWindow&) = delete;

    /// The connection's descriptor, for poll().
    int fd() const noexcept;
    /// Dispatches queued events and sends queued requests; call before poll().
    Status prepare();
    /// After poll(): reads and dispatches what arrived (`readable`), or cancels the read.
    Status dispatch(bool readable);

    wl_surface* surface() const noexcept { return m_surface; }
    wl_shm* shm() const noexcept { return m_shm; }
    const std::vector<std::uint32_t>& shmFormats() const noexcept { return m_shm_formats; }
    const char* shellName() const noexcept { return m_ivi_surface != nullptr ? "ivi-shell" : "xdg-shell"; }

    /// The compositor asked for a size (0 = the client's choice, xdg): true once per configure.
    bool takeConfigure(int* width, int* height);
    /// Whether the surface may be committed with a buffer (xdg: after the first configure).
    bool canDraw() const noexcept { return m_configured; }
    /// Commits the surface, acknowledging a pending xdg configure first.
    void commit();
    /// The compositor asked to close the window (xdg_toplevel.close).
    bool closeRequested() const noexcept { return m_close_requested; }

    struct Listeners;  // the C callbacks (wayland_window.cpp)

private:
    WaylandWindow() = default;
    Status bindGlobals(const WindowOptions& options);
    Status createRole(const WindowOptions& options);
    Status connectionError(const char* what);

    wl_display* m_display = nullptr;
    wl_registry* m_registry = nullptr;
    wl_compositor* m_compositor = nullptr;
    wl_shm* m_shm = nullptr;
    xdg_wm_base* m_xdg_wm_base = nullptr;
    ivi_application* m_ivi_application = nullptr;
    wl_surface* m_surface = nullptr;
    ivi_surface* m_ivi_surface = nullptr;
    xdg_surface* m_xdg_surface = nullptr;
    xdg_toplevel* m_xdg_toplevel = nullptr;
    std::vector<std::uint32_t> m_shm_formats;
    std::string m_display_name;
    bool m_configured = false;
    bool m_configure_pending = false;  ///< a size to take
    int m_configure_width = 0;
    int m_configure_height = 0;
    int m_toplevel_width = 0;  ///< xdg_toplevel.configure, applied at xdg_surface.configure
    int m_toplevel_height = 0;
    std::uint32_t m_ack_serial = 0;
    bool m_ack_pending = false;
    bool m_close_requested = false;
};

}  // namespace navmap::ipc::wayland
