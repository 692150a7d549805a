// SPDX-License-Identifier: Apache-2.0
#pragma once
// The route as a control-IPC message, one JSON line in the protocol of docs/ipc.md:
//   {"cmd":"set_route","id":"r1","points":[[lat,lon],...],"maneuvers":[{"index":4,"type":"turn_right"},...]}
// Send it with ipc::ControlClient::request(); the reply is {"ok":true,...} or {"ok":false,"error":...}.

#include <string>
#include <string_view>

#include "navmap/map/projection.h"
#include "navmap/sim/drive_route.h"

namespace navmap::sim {

/// JSON text without the trailing newline. Points in degrees with 7 decimals (1 cm).
std::string setRouteMessage(const DriveRoute& route, const map::Projection& projection, const std::string& id);

/// True for a reply object with "ok": true; malformed JSON or anything else gives false.
bool replyIsOk(std::string_view reply);

}  // namespace navmap::sim
