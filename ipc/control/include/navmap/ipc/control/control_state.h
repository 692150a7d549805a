// SPDX-License-Identifier: Apache-2.0
#pragma once
// ControlState: a ready-made ControlHandler that keeps what the control socket set (route, view
// per display, style) as immutable snapshots. The server thread replaces them; any thread reads
// the latest with route()/view() without waiting on the socket (the snapshots are swapped
// atomically, MapLibre Immutable<> style).

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "navmap/ipc/control/control_handler.h"

namespace navmap::ipc {

/// The active route as set by set_route.
struct RouteState {
    std::string id;
    std::vector<GeoCoordinate> points;
    std::vector<Maneuver> maneuvers;
    std::uint64_t version = 0;  ///< increases with every set_route/clear_route
};

struct DisplayView {
    ViewMode mode = ViewMode::Auto;
    ViewOrientation orientation = ViewOrientation::HeadingUp;
    bool orientation_set = false;  ///< a set_view gave `orientation` (else the display's own applies)
    /// A MapLibre-convention camera set by set_view; it wins over `mode`. Cleared by
    /// "camera": null and by a set_view that gives a mode without a camera.
    std::optional<ViewCamera> camera;
};

/// View settings of all displays and the map style.
struct ViewState {
    std::map<std::string, DisplayView, std::less<>> displays;
    MapStyle style = MapStyle::Day;
    /// `style` came from a set_style of the HMI (SetStyleCommand::configured false).
    bool style_from_hmi = false;
    Ground ground = Ground::LandCover;
    std::uint64_t version = 0;
};

class ControlState final : public ControlHandler {
public:
    /// `displays`: the display names set_view accepts (e.g. cluster, hud, center); empty = any.
    explicit ControlState(std::set<std::string, std::less<>> displays = {});

    /// Latest route, or null when none is set. Thread-safe, lock-free for the reader.
    [[nodiscard]] std::shared_ptr<const RouteState> route() const { return m_route.load(); }
    /// Latest view settings (never null). Thread-safe.
    [[nodiscard]] std::shared_ptr<const ViewState> view() const { return m_view.load(); }

    /// Supplies the get_status object (called on the server thread); default: route and view.
    void setStatusProvider(std::function<nlohmann::json()> provider) { m_status_provider = std::move(provider); }

    Status setRoute(const SetRouteCommand& command) override;
    Status clearRoute() override;
    Status setView(const SetViewCommand& command) override;
    Status setStyle(const SetStyleCommand& command) override;
    nlohmann::json status() override;

private:
    std::set<std::string, std::less<>> m_allowed_displays;
    std::atomic<std::shared_ptr<const RouteState>> m_route;
    std::atomic<std::shared_ptr<const ViewState>> m_view;
    std::uint64_t m_route_version = 0;
    std::function<nlohmann::json()> m_status_provider;
};

}  // namespace navmap::ipc
