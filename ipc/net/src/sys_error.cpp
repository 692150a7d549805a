// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/net/sys_error.h"

#include <cerrno>
#include <cstring>

namespace navmap::ipc::net {

std::string sysError(std::string_view call, std::string_view object, int err) {
    std::string text(call);
    text += '(';
    text += object;
    text += "): ";
    text += std::strerror(err);
    return text;
}

std::string sysError(std::string_view call, std::string_view object) {
    const int err = errno;  // before any allocation below can touch it
    return sysError(call, object, err);
}

}  // namespace navmap::ipc::net
