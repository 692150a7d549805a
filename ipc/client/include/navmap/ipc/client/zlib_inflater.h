// SPDX-License-Identifier: Apache-2.0
#pragma once
// zlibInflater(): the FrameInflater navmap's own programs (navmap-view, navmap-soak, tests) pass
// to StreamClient for payload zlib. Lives beside the PNG writer in navmap_stream_tools, not in
// libnavmap-client, which links no compression library.

#include "navmap/ipc/client/stream_client.h"

namespace navmap::ipc {

/// Inflates with zlib's uncompress(); true only when the payload inflates to exactly outBytes.
FrameInflater zlibInflater();

}  // namespace navmap::ipc
