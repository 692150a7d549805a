#pragma once
// The HTML viewer FrameServer serves at GET / (private to ipc/src/stream).

#include <string>

namespace navmap::ipc::stream_detail {

/// A self-contained page: the live MJPEG stream of `profile` and the /status JSON, refreshed
/// every second. No external resources (the ECU has no internet).
std::string viewerPage(const std::string& profile);

}  // namespace navmap::ipc::stream_detail
