// SPDX-License-Identifier: Apache-2.0
#pragma once
// The control socket's and the frame server's settings from navmapd's configuration ([control],
// [stream], the profiles it renders).

#include "config.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/stream/frame_server.h"

namespace navmap::daemon {

/// Throws std::runtime_error when control.group names no group.
ipc::ControlServerConfig controlServerConfig(const DaemonConfig& config);

/// Everything but the metrics and status callbacks. Throws std::runtime_error when stream.group
/// names no group.
ipc::FrameServerOptions frameServerOptions(const DaemonConfig& config);

}  // namespace navmap::daemon
