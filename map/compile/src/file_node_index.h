// SPDX-License-Identifier: Apache-2.0
#pragma once
// The node-location index of the bounded-memory compile: libosmium's SparseFileArray (sorted
// id/location pairs in a file mapped into memory, so its pages are the kernel's to write back
// and drop), with the file's blocks allocated ahead of the mapping. A write into a mapped page
// that has no block on a full disk would be SIGBUS; fallocate() turns that into an error naming
// the file. Private to navmap_map.

#include <osmium/index/map.hpp>
#include <osmium/index/map/sparse_file_array.hpp>
#include <osmium/osm/location.hpp>
#include <osmium/osm/types.hpp>

#include <filesystem>
#include <memory>

namespace navmap::map::detail {

using NodeIndex = osmium::index::map::Map<osmium::unsigned_object_id_type, osmium::Location>;

class FileNodeIndex : public NodeIndex {
public:
    /// Creates the index file `path`; throws SpillError naming it when it cannot.
    explicit FileNodeIndex(std::filesystem::path path);
    ~FileNodeIndex() noexcept override;

    void set(osmium::unsigned_object_id_type id, osmium::Location value) override;
    [[nodiscard]] osmium::Location get(osmium::unsigned_object_id_type id) const override;
    [[nodiscard]] osmium::Location get_noexcept(osmium::unsigned_object_id_type id) const noexcept override;
    [[nodiscard]] std::size_t size() const override;
    [[nodiscard]] std::size_t used_memory() const override;
    void clear() override;
    void sort() override;

private:
    void allocate(std::uint64_t entries);
    using Array = osmium::index::map::SparseFileArray<osmium::unsigned_object_id_type, osmium::Location>;
    std::filesystem::path m_path;
    int m_fd = -1;
    std::uint64_t m_allocated = 0;  // entries with blocks on disk
    std::uint64_t m_entries = 0;
    std::unique_ptr<Array> m_array;
};

}  // namespace navmap::map::detail
