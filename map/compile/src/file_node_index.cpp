// SPDX-License-Identifier: Apache-2.0
#include "file_node_index.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "navmap/map/compile/spill_file.h"

namespace navmap::map::detail {

namespace {

using Entry = std::pair<osmium::unsigned_object_id_type, osmium::Location>;
// libosmium grows the mapping by this many entries at a time (mmap_vector_base.hpp).
constexpr std::uint64_t kGrowth = osmium::detail::mmap_vector_size_increment;

}  // namespace

FileNodeIndex::FileNodeIndex(std::filesystem::path path) : m_path(std::move(path)) {
    m_fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (m_fd < 0) throw SpillError("open(" + m_path.string() + "): " + std::strerror(errno));
    try {
        allocate(0);
        m_array = std::make_unique<Array>(m_fd);
    } catch (const std::system_error& e) {
        ::close(m_fd);
        throw SpillError(m_path.string() + ": " + e.what());
    } catch (...) {
        ::close(m_fd);
        throw;
    }
}

FileNodeIndex::~FileNodeIndex() noexcept {
    m_array.reset();
    if (m_fd >= 0) ::close(m_fd);
}

void FileNodeIndex::allocate(std::uint64_t entries) {
    // Ahead of libosmium's capacity, which is at most entries + kGrowth.
    if (entries + 2 * kGrowth <= m_allocated) return;
    const std::uint64_t want = entries + 4 * kGrowth;
    const int err = ::fallocate(m_fd, FALLOC_FL_KEEP_SIZE, 0, static_cast<off_t>(want * sizeof(Entry)));
    if (err != 0 && errno != EOPNOTSUPP) {
        throw SpillError("fallocate(" + m_path.string() + ", " + std::to_string(want * sizeof(Entry)) +
                         " bytes): " + std::strerror(errno));
    }
    m_allocated = want;
}

void FileNodeIndex::set(osmium::unsigned_object_id_type id, osmium::Location value) {
    allocate(m_entries + 1);
    try {
        m_array->set(id, value);
    } catch (const std::system_error& e) {
        throw SpillError(m_path.string() + ": " + e.what());
    }
    ++m_entries;
}

osmium::Location FileNodeIndex::get(osmium::unsigned_object_id_type id) const { return m_array->get(id); }

osmium::Location FileNodeIndex::get_noexcept(osmium::unsigned_object_id_type id) const noexcept {
    return m_array->get_noexcept(id);
}

std::size_t FileNodeIndex::size() const { return m_array->size(); }

std::size_t FileNodeIndex::used_memory() const { return m_array->used_memory(); }

void FileNodeIndex::clear() { m_array->clear(); }

void FileNodeIndex::sort() { m_array->sort(); }

}  // namespace navmap::map::detail
