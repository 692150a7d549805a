// SPDX-License-Identifier: Apache-2.0
#pragma once
// The JSON-lines control protocol (docs/ipc.md): parsing and validating one request line into a
// ControlCommand, and writing replies and events. Pure functions, thread-safe, no I/O.

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "navmap/ipc/control/control_command.h"

namespace navmap::ipc {

/// Outcome of parsing one line: a command, or an error naming the problem. `cmd` and `id` are
/// filled from the request as far as they could be read, so the error reply can echo them.
struct ControlParse {
    std::optional<ControlCommand> command;
    std::string error;              ///< empty when command is set
    std::string cmd;                ///< the request's "cmd" when it was a string
    std::optional<std::string> id;  ///< the request's "id" when it was a string
};

/// Parses one line (without the newline). Never throws; every malformed or out-of-range input
/// yields an error such as `points[3]: latitude 95 out of range [-90, 90]`.
ControlParse parseControlLine(std::string_view line, const ControlLimits& limits = {});

/// {"ok":true,"cmd":...,"id":...} plus the members of `extra` (an object or null). One line, no newline.
std::string controlOkReply(std::string_view cmd, const std::optional<std::string>& id,
                           const nlohmann::json& extra = nullptr);
/// {"ok":false,"cmd":...,"id":...,"error":...}; cmd/id are left out when empty/absent.
std::string controlErrorReply(std::string_view cmd, const std::optional<std::string>& id, std::string_view error);
/// {"event":"route_progress",...} etc. One line, no newline.
std::string controlEventLine(const ControlEvent& event);

}  // namespace navmap::ipc
