// SPDX-License-Identifier: Apache-2.0
#include "spill_dir.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "navmap/map/spill_file.h"

namespace navmap::map::detail {

SpillDir::SpillDir(const std::filesystem::path& parent, std::function<void(const std::string&)> log)
    : m_log(std::move(log)) {
    std::string name = (parent.empty() ? std::filesystem::path(".") : parent) / "navmap-spill-XXXXXX";
    if (::mkdtemp(name.data()) == nullptr) throw SpillError("mkdtemp(" + name + "): " + std::strerror(errno));
    m_path = name;
}

SpillDir::~SpillDir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
    if (ec && m_log) m_log("warning: cannot remove " + m_path.string() + ": " + ec.message());
}

}  // namespace navmap::map::detail
