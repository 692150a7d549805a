// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/control/control_state.h"

#include "navmap/ipc/control/control_protocol.h"

namespace navmap::ipc {

ControlState::ControlState(std::set<std::string, std::less<>> displays) : m_allowed_displays(std::move(displays)) {
    auto view = std::make_shared<ViewState>();
    for (const auto& d : m_allowed_displays) {
        view->displays.emplace(d, DisplayView{});
    }
    m_view.store(std::move(view));
}

Status ControlState::setRoute(const SetRouteCommand& command) {
    auto route = std::make_shared<RouteState>();
    route->id = command.route_id;
    route->points = command.points;
    route->maneuvers = command.maneuvers;
    route->version = ++m_route_version;
    m_route.store(std::move(route));
    return {};
}

Status ControlState::clearRoute() {
    ++m_route_version;
    m_route.store(nullptr);
    return {};
}

Status ControlState::setView(const SetViewCommand& command) {
    if (!m_allowed_displays.empty() && !m_allowed_displays.contains(command.display)) {
        std::string names;
        for (const auto& d : m_allowed_displays) {
            names += names.empty() ? "" : " | ";
            names += d;
        }
        return Error{"unknown display \"" + command.display + "\" (expected " + names + ")"};
    }
    const auto current = m_view.load();
    auto next = std::make_shared<ViewState>(*current);
    auto& d = next->displays[command.display];
    if (command.mode) {
        d.mode = *command.mode;
    }
    if (command.orientation) {
        d.orientation = *command.orientation;
        d.orientation_set = true;
    }
    if (command.camera) {
        d.camera = command.camera;
    } else if (command.clear_camera || command.mode) {
        d.camera.reset();  // a mode without a camera: the display follows the mode again
    }
    ++next->version;
    m_view.store(std::move(next));
    return {};
}

Status ControlState::setStyle(const SetStyleCommand& command) {
    auto next = std::make_shared<ViewState>(*m_view.load());
    if (command.style) {
        next->style = *command.style;
        next->style_from_hmi = !command.configured;
    }
    if (command.ground) next->ground = *command.ground;
    ++next->version;
    m_view.store(std::move(next));
    return {};
}

nlohmann::json ControlState::status() {
    if (m_status_provider) {
        return m_status_provider();
    }
    nlohmann::json j = nlohmann::json::object();
    const auto route = m_route.load();
    if (route) {
        j["route"] = {{"id", route->id}, {"points", route->points.size()}, {"maneuvers", route->maneuvers.size()}};
    } else {
        j["route"] = nullptr;
    }
    const auto view = m_view.load();
    j["style"] = mapStyleName(view->style);
    j["ground"] = groundName(view->ground);
    nlohmann::json displays = nlohmann::json::object();
    for (const auto& [name, d] : view->displays) {
        displays[name] = {{"mode", viewModeName(d.mode)}, {"orientation", viewOrientationName(d.orientation)}};
        if (d.camera) {
            nlohmann::json camera = {{"zoom", d.camera->zoom}, {"pitch", d.camera->pitch_deg}};
            if (d.camera->bearing_deg) {
                camera["bearing"] = *d.camera->bearing_deg;
            }
            displays[name]["camera"] = std::move(camera);
        } else {
            displays[name]["camera"] = nullptr;
        }
    }
    j["displays"] = std::move(displays);
    return j;
}

}  // namespace navmap::ipc
