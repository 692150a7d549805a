// SPDX-License-Identifier: Apache-2.0
#pragma once
// Syscall error text, the same everywhere: the call, the object it acted on and strerror(),
// "bind(/run/navmap/frames.sock): Permission denied" (as Redis anet.c words them).

#include <string>
#include <string_view>

namespace navmap::ipc::net {

/// "<call>(<object>): <strerror(err)>". `call` may carry the option or flag that failed,
/// "setsockopt(CAN_RAW_FILTER)"; `object` is the path, interface or peer.
std::string sysError(std::string_view call, std::string_view object, int err);

/// The same with the calling thread's errno (read before anything can change it).
std::string sysError(std::string_view call, std::string_view object);

}  // namespace navmap::ipc::net
