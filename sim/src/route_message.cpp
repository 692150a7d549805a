// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/route_message.h"

#include <cmath>
#include <nlohmann/json.hpp>

namespace navmap::sim {

namespace {

double round7(double deg) { return std::round(deg * 1e7) / 1e7; }

}  // namespace

std::string setRouteMessage(const DriveRoute& route, const map::Projection& projection, const std::string& id) {
    nlohmann::json points = nlohmann::json::array();
    for (const map::RoutePoint& p : route.line) {
        double lat = 0.0;
        double lon = 0.0;
        projection.reverse(p.position, lat, lon);
        points.push_back({round7(lat), round7(lon)});
    }
    // The protocol accepts exactly index/end_index/type/text/exit per maneuver (docs/ipc.md).
    nlohmann::json maneuvers = nlohmann::json::array();
    for (const Maneuver& m : route.maneuvers) {
        nlohmann::json j{{"index", m.point}, {"type", m.type}};
        if (!m.text.empty()) j["text"] = m.text;
        if (m.exit > 0) j["exit"] = m.exit;
        if (m.end_point > m.point) j["end_index"] = m.end_point;
        maneuvers.push_back(std::move(j));
    }
    const nlohmann::json msg{
        {"cmd", "set_route"}, {"id", id}, {"points", std::move(points)}, {"maneuvers", std::move(maneuvers)}};
    return msg.dump();
}

bool replyIsOk(std::string_view reply) {
    const auto j = nlohmann::json::parse(reply, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return false;
    const auto it = j.find("ok");
    return it != j.end() && it->is_boolean() && it->get<bool>();
}

}  // namespace navmap::sim
