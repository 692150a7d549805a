// SPDX-License-Identifier: Apache-2.0
#pragma once
// Multipolygon areas for the bounded compile (docs/tile-store.md "Bounded memory"): libosmium's
// MultipolygonManager keeps every member way of a multipolygon relation in memory until the
// relation is complete, which on a large region is most of them for most of the read. This
// manager does the same work with the member ways in a spill file: it keeps the relations and,
// per member, its id, its relation and where its way lies in the file, and reads a relation's
// ways back when the last one has come.
//
// It follows MultipolygonManager<Assembler> step by step (the same relations and members are
// wanted, relations complete at the same way, complete_relation()/after_way() are the same and
// areas leave through a CallbackBuffer flushed at the same points), so that the areas come out
// in the same order with the same bytes: a bounded store equals the in-memory one. Private to
// navmap_map.

#include <osmium/area/assembler.hpp>
#include <osmium/handler.hpp>
#include <osmium/memory/buffer.hpp>
#include <osmium/memory/callback_buffer.hpp>
#include <osmium/osm/relation.hpp>
#include <osmium/osm/way.hpp>
#include <osmium/tags/tags_filter.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "navmap/map/compile/spill_file.h"

namespace navmap::map::detail {

class DiskMultipolygonManager : public osmium::handler::Handler {
public:
    /// The member ways go to `ways_file` (created; SpillError naming it when it cannot be).
    DiskMultipolygonManager(osmium::area::Assembler::config_type config, osmium::TagsFilter filter,
                            std::filesystem::path ways_file);
    ~DiskMultipolygonManager();
    DiskMultipolygonManager(const DiskMultipolygonManager&) = delete;
    DiskMultipolygonManager& operator=(const DiskMultipolygonManager&) = delete;

    // ---- first pass (osmium::relations::read_relations()) ----
    void relation(const osmium::Relation& relation);
    void prepare_for_lookup();  // NOLINT(readability-identifier-naming): read_relations() calls it so

    // ---- second pass ----
    class SecondPass : public osmium::handler::Handler {
    public:
        explicit SecondPass(DiskMultipolygonManager& manager) : m_manager(manager) {}
        void way(const osmium::Way& way) { m_manager.handleWay(way); }
        void flush() { m_manager.m_output.flush(); }

    private:
        DiskMultipolygonManager& m_manager;
    };
    /// The handler of the second pass; `callback` takes each buffer of finished areas.
    SecondPass& handler(const std::function<void(osmium::memory::Buffer&&)>& callback);

    /// Member ways written to the file so far, and relations made into areas.
    [[nodiscard]] std::uint64_t memberWays() const { return m_member_ways; }
    [[nodiscard]] std::uint64_t completeRelations() const { return m_complete; }

private:
    struct Member {
        std::int64_t way_id;
        std::size_t member_num;
        std::size_t relation;     // index into m_relation_offsets
        std::uint64_t spill = 0;  // where the way lies in the file; 0: not come yet
        bool operator<(const Member& o) const {
            return std::tie(way_id, member_num, relation) < std::tie(o.way_id, o.member_num, o.relation);
        }
    };

    [[nodiscard]] bool wanted(const osmium::Relation& relation) const;
    void handleWay(const osmium::Way& way);
    void completeRelation(std::size_t relation);
    void afterWay(const osmium::Way& way);

    osmium::area::Assembler::config_type m_config;
    osmium::TagsFilter m_filter;
    osmium::memory::Buffer m_relations{1 << 20, osmium::memory::Buffer::auto_grow::yes};
    std::vector<std::size_t> m_relation_offsets;
    std::vector<std::uint32_t> m_missing;  // per relation: member ways not come yet
    std::vector<Member> m_members;         // sorted after the first pass
    SpillWriter m_ways_out;
    std::unique_ptr<SpillReader> m_ways_in;
    std::uint64_t m_flushed = 0;  // bytes of the file the reader can see
    osmium::memory::CallbackBuffer m_output;
    SecondPass m_second_pass{*this};
    std::uint64_t m_member_ways = 0, m_complete = 0;
};

}  // namespace navmap::map::detail
