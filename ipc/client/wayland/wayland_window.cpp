// SPDX-License-Identifier: Apache-2.0
#include "wayland_window.h"

#include <wayland-client.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "ivi-application-client-protocol.h"
#include "xdg-shell-client-protocol.h"

namespace navmap::ipc::wayland {

struct WaylandWindow::Listeners {
    static void global(void* data, wl_registry* registry, std::uint32_t name, const char* interface,
                       std::uint32_t version) {
        auto* w = static_cast<WaylandWindow*>(data);
        const auto bind = [&](const wl_interface* iface, std::uint32_t most) {
            return wl_registry_bind(registry, name, iface, std::min(version, most));
        };
        if (std::strcmp(interface, wl_compositor_interface.name) == 0 && w->m_compositor == nullptr) {
            w->m_compositor = static_cast<wl_compositor*>(bind(&wl_compositor_interface, 4));
        } else if (std::strcmp(interface, wl_shm_interface.name) == 0 && w->m_shm == nullptr) {
            w->m_shm = static_cast<wl_shm*>(bind(&wl_shm_interface, 1));
            wl_shm_add_listener(w->m_shm, &kShm, w);
        } else if (std::strcmp(interface, xdg_wm_base_interface.name) == 0 && w->m_xdg_wm_base == nullptr) {
            w->m_xdg_wm_base = static_cast<xdg_wm_base*>(bind(&xdg_wm_base_interface, 2));
            xdg_wm_base_add_listener(w->m_xdg_wm_base, &kWmBase, w);
        } else if (std::strcmp(interface, ivi_application_interface.name) == 0 && w->m_ivi_application == nullptr) {
            w->m_ivi_application = static_cast<ivi_application*>(bind(&ivi_application_interface, 1));
        }
    }
    static void globalRemove(void* /*data*/, wl_registry* /*registry*/, std::uint32_t /*name*/) {}
    static void shmFormat(void* data, wl_shm* /*shm*/, std::uint32_t format) {
        static_cast<WaylandWindow*>(data)->m_shm_formats.push_back(format);
    }
    static void ping(void* /*data*/, xdg_wm_base* base, std::uint32_t serial) { xdg_wm_base_pong(base, serial); }
    static void xdgConfigure(void* data, xdg_surface* /*surface*/, std::uint32_t serial) {
        auto* w = static_cast<WaylandWindow*>(data);
        w->m_ack_serial = serial;
        w->m_ack_pending = true;
        w->m_configured = true;
        w->m_configure_pending = true;
        w->m_configure_width = w->m_toplevel_width;
        w->m_configure_height = w->m_toplevel_height;
    }
    static void toplevelConfigure(void* data, xdg_toplevel* /*toplevel*/, std::int32_t width, std::int32_t height,
                                  wl_array* /*states*/) {
        auto* w = static_cast<WaylandWindow*>(data);
        w->m_toplevel_width = width;
        w->m_toplevel_height = height;
    }
    static void toplevelClose(void* data, xdg_toplevel* /*toplevel*/) {
        static_cast<WaylandWindow*>(data)->m_close_requested = true;
    }
    static void iviConfigure(void* data, ivi_surface* /*surface*/, std::int32_t width, std::int32_t height) {
        auto* w = static_cast<WaylandWindow*>(data);
        w->m_configure_pending = true;
        w->m_configure_width = width;
        w->m_configure_height = height;
    }

    static constexpr wl_registry_listener kRegistry = {global, globalRemove};
    static constexpr wl_shm_listener kShm = {shmFormat};
    static constexpr xdg_wm_base_listener kWmBase = {ping};
    static constexpr xdg_surface_listener kXdgSurface = {xdgConfigure};
    // configure_bounds and wm_capabilities are versions 4 and 5: xdg_wm_base is bound at 2.
    static constexpr xdg_toplevel_listener kToplevel = {toplevelConfigure, toplevelClose, nullptr, nullptr};
    static constexpr ivi_surface_listener kIviSurface = {iviConfigure};
};

namespace {

// Where libwayland looked, for the message when nobody answered there.
std::string displayDescription() {
    const char* name = std::getenv("WAYLAND_DISPLAY");
    const char* dir = std::getenv("XDG_RUNTIME_DIR");
    if (name != nullptr && name[0] == '/') return std::string("WAYLAND_DISPLAY=") + name;
    return std::string("WAYLAND_DISPLAY=") + (name != nullptr && name[0] != '\0' ? name : "(not set: wayland-0)") +
           " in XDG_RUNTIME_DIR=" + (dir != nullptr && dir[0] != '\0' ? dir : "(not set)");
}

}  // namespace

Result<std::unique_ptr<WaylandWindow>> WaylandWindow::open(const WindowOptions& options) {
    const char* name = std::getenv("WAYLAND_DISPLAY");
    const char* dir = std::getenv("XDG_RUNTIME_DIR");
    if ((name == nullptr || name[0] == '\0') && (dir == nullptr || dir[0] == '\0')) {
        return Error{"no Wayland compositor: WAYLAND_DISPLAY and XDG_RUNTIME_DIR are not set"};
    }
    std::unique_ptr<WaylandWindow> w(new WaylandWindow());
    w->m_display_name = displayDescription();
    w->m_display = wl_display_connect(nullptr);
    if (w->m_display == nullptr) {
        const int err = errno;
        return Error{"no Wayland compositor at " + w->m_display_name + ": " + std::strerror(err)};
    }
    if (auto s = w->bindGlobals(options); !s) return Error{s.message()};
    if (auto s = w->createRole(options); !s) return Error{s.message()};
    return w;
}

WaylandWindow::~WaylandWindow() {
    if (m_display == nullptr) return;
    if (m_ivi_surface != nullptr) ivi_surface_destroy(m_ivi_surface);
    if (m_xdg_toplevel != nullptr) xdg_toplevel_destroy(m_xdg_toplevel);
    if (m_xdg_surface != nullptr) xdg_surface_destroy(m_xdg_surface);
    if (m_surface != nullptr) wl_surface_destroy(m_surface);
    if (m_ivi_application != nullptr) ivi_application_destroy(m_ivi_application);
    if (m_xdg_wm_base != nullptr) xdg_wm_base_destroy(m_xdg_wm_base);
    if (m_shm != nullptr) wl_shm_destroy(m_shm);
    if (m_compositor != nullptr) wl_compositor_destroy(m_compositor);
    if (m_registry != nullptr) wl_registry_destroy(m_registry);
    wl_display_flush(m_display);
    wl_display_disconnect(m_display);
}

Status WaylandWindow::bindGlobals(const WindowOptions& options) {
    m_registry = wl_display_get_registry(m_display);
    wl_registry_add_listener(m_registry, &Listeners::kRegistry, this);
    // The globals, then the events of what was bound (wl_shm's formats).
    for (int i = 0; i < 2; ++i) {
        if (wl_display_roundtrip(m_display) < 0) return connectionError("reading the compositor's globals");
    }
    if (m_compositor == nullptr)
        return Error{"the Wayland compositor at " + m_display_name + " offers no wl_compositor"};
    if (m_shm == nullptr) return Error{"the Wayland compositor at " + m_display_name + " offers no wl_shm"};
    if (options.shell == ShellKind::Ivi && m_ivi_application == nullptr) {
        return Error{"the Wayland compositor at " + m_display_name +
                     " offers no ivi_application (--shell ivi needs Weston's ivi-shell)"};
    }
    if (options.shell == ShellKind::Xdg && m_xdg_wm_base == nullptr) {
        return Error{"the Wayland compositor at " + m_display_name + " offers no xdg_wm_base (--shell xdg)"};
    }
    if (m_ivi_application == nullptr && m_xdg_wm_base == nullptr) {
        return Error{"the Wayland compositor at " + m_display_name +
                     " offers neither ivi_application (ivi-shell) nor xdg_wm_base (xdg-shell)"};
    }
    return {};
}

Status WaylandWindow::createRole(const WindowOptions& options) {
    m_surface = wl_compositor_create_surface(m_compositor);
    const bool ivi = options.shell == ShellKind::Ivi || (options.shell == ShellKind::Auto && m_ivi_application);
    if (ivi) {
        m_ivi_surface = ivi_application_surface_create(m_ivi_application, options.ivi_id, m_surface);
        ivi_surface_add_listener(m_ivi_surface, &Listeners::kIviSurface, this);
        m_configured = true;  // an ivi_surface may show a buffer at once; the controller places it
    } else {
        m_xdg_surface = xdg_wm_base_get_xdg_surface(m_xdg_wm_base, m_surface);
        xdg_surface_add_listener(m_xdg_surface, &Listeners::kXdgSurface, this);
        m_xdg_toplevel = xdg_surface_get_toplevel(m_xdg_surface);
        xdg_toplevel_add_listener(m_xdg_toplevel, &Listeners::kToplevel, this);
        xdg_toplevel_set_title(m_xdg_toplevel, options.title.c_str());
        xdg_toplevel_set_app_id(m_xdg_toplevel, options.app_id.c_str());
        if (options.fullscreen) xdg_toplevel_set_fullscreen(m_xdg_toplevel, nullptr);
        wl_surface_commit(m_surface);  // no buffer: asks for the first configure
    }
    // A role error (ivi_id taken) arrives here rather than in the loop.
    if (wl_display_roundtrip(m_display) < 0) return connectionError("creating the surface");
    return {};
}

Status WaylandWindow::connectionError(const char* what) {
    const int err = wl_display_get_error(m_display);
    if (err == EPROTO) {
        const wl_interface* iface = nullptr;
        std::uint32_t id = 0;
        const std::uint32_t code = wl_display_get_protocol_error(m_display, &iface, &id);
        const std::string name = iface != nullptr ? iface->name : "?";
        std::string why = "Wayland protocol error while " + std::string(what) + ": " + name + "#" + std::to_string(id) +
                          " error " + std::to_string(code);
        if (name == "ivi_application" && code == IVI_APPLICATION_ERROR_IVI_ID) {
            why += " (the ivi_id is already used by another surface)";
        }
        return Error{why};
    }
    return Error{"the Wayland compositor (" + m_display_name + ") closed the connection while " + what + ": " +
                 std::strerror(err != 0 ? err : EPIPE)};
}

int WaylandWindow::fd() const noexcept { return wl_display_get_fd(m_display); }

Status WaylandWindow::prepare() {
    while (wl_display_prepare_read(m_display) != 0) {
        if (wl_display_dispatch_pending(m_display) < 0) return connectionError("dispatching events");
    }
    if (wl_display_flush(m_display) < 0 && errno != EAGAIN) {
        wl_display_cancel_read(m_display);
        return connectionError("sending requests");
    }
    return {};
}

Status WaylandWindow::dispatch(bool readable) {
    if (readable) {
        if (wl_display_read_events(m_display) < 0) return connectionError("reading events");
    } else {
        wl_display_cancel_read(m_display);
    }
    if (wl_display_dispatch_pending(m_display) < 0) return connectionError("dispatching events");
    return {};
}

bool WaylandWindow::takeConfigure(int* width, int* height) {
    if (!m_configure_pending) return false;
    m_configure_pending = false;
    *width = m_configure_width;
    *height = m_configure_height;
    return true;
}

void WaylandWindow::commit() {
    if (m_ack_pending) {
        xdg_surface_ack_configure(m_xdg_surface, m_ack_serial);
        m_ack_pending = false;
    }
    wl_surface_commit(m_surface);
}

}  // namespace navmap::ipc::wayland
