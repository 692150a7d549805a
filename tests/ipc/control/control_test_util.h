// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers for control-socket tests: a private temporary directory and an fd count (libosmium
// count_fds style) to check that nothing leaks.

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "open_fds.h"

namespace navmap::test {

/// mkdtemp directory under /tmp (short, so socket paths fit sun_path), removed at scope exit.
class TempDir {
public:
    TempDir() {
        char tmpl[] = "/tmp/navmap-ctl-XXXXXX";
        if (::mkdtemp(tmpl) != nullptr) {
            m_path = tmpl;
        }
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] std::string file(const std::string& name) const { return m_path + "/" + name; }

private:
    std::string m_path;
};

}  // namespace navmap::test
