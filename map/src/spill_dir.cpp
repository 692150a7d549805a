// SPDX-License-Identifier: Apache-2.0
#include "spill_dir.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "navmap/map/spill_file.h"

namespace navmap::map::detail {

SpillDir::SpillDir(const std::filesystem::path& parent, std::function<void(const std::string&)> log)
    : m_log(std::move(log)) {
    const std::string pattern = (parent.empty() ? std::filesystem::path(".") : parent) / "navmap-spill-XXXXXX";
    std::string name = pattern;  // mkdtemp() fills the Xs in, even when it fails
    if (::mkdtemp(name.data()) == nullptr) throw SpillError("mkdtemp(" + pattern + "): " + std::strerror(errno));
    m_path = name;
}

SpillDir::~SpillDir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
    if (ec && m_log) m_log("warning: cannot remove " + m_path.string() + ": " + ec.message());
}

}  // namespace navmap::map::detail
