// SPDX-License-Identifier: Apache-2.0
#pragma once
// File descriptors open in this process (entries of /proc/self/fd, including the one used to
// read it): tests compare the count before and after to find leaked sockets and fds.

namespace navmap::test {

int countOpenFds();

}  // namespace navmap::test
