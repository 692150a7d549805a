// SPDX-License-Identifier: Apache-2.0
#include "open_fds.h"

#include <dirent.h>

namespace navmap::test {

int countOpenFds() {
    int n = 0;
    if (DIR* d = ::opendir("/proc/self/fd")) {
        while (::readdir(d) != nullptr) ++n;
        ::closedir(d);
    }
    return n;
}

}  // namespace navmap::test
