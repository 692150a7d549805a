// SPDX-License-Identifier: Apache-2.0
#pragma once
// ControlHandler: the daemon side of the control socket. ControlServer calls it for every valid
// command, on the server's thread (the thread that runs pollOnce()). An implementation applies
// the command to its state and publishes immutable snapshots for the render thread (see
// ControlState); it must not block.

#include <nlohmann/json.hpp>

#include "navmap/ipc/control/control_command.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

class ControlHandler {
public:
    virtual ~ControlHandler() = default;

    /// A failed Status becomes an error reply carrying its message; nothing may change then.
    virtual Status setRoute(const SetRouteCommand& command) = 0;
    virtual Status clearRoute() = 0;
    virtual Status setView(const SetViewCommand& command) = 0;
    virtual Status setStyle(const SetStyleCommand& command) = 0;
    /// The "status" object of the get_status reply (must be a JSON object).
    virtual nlohmann::json status() = 0;
};

}  // namespace navmap::ipc
