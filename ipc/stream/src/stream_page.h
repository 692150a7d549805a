// SPDX-License-Identifier: Apache-2.0
#pragma once
// The HTML viewer FrameServer serves at GET / (private to ipc/stream).

#include <string>
#include <vector>

namespace navmap::ipc::stream_detail {

/// A self-contained page: the live MJPEG stream of `profile`, one button per profile in
/// `profiles` (the defaults of docs/architecture.md "Display profiles" when empty), the map data attribution under the
/// stream, and the /status JSON refreshed every second. No external resources (the ECU has no internet).
std::string viewerPage(const std::string& profile, const std::vector<std::string>& profiles);

}  // namespace navmap::ipc::stream_detail
