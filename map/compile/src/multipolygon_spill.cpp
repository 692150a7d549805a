// SPDX-License-Identifier: Apache-2.0
// GCC 12 reports a false -Wstringop-overread inside libosmium's area builder once it is inlined
// here, as in compile_read.cpp (osmium/builder/osm_object_builder.hpp reads a NUL-terminated tag).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif

#include "multipolygon_spill.h"

#include <osmium/osm/location.hpp>
#include <osmium/tags/taglist.hpp>

#include <algorithm>
#include <cstring>
#include <span>
#include <tuple>
#include <utility>

namespace navmap::map::detail {

DiskMultipolygonManager::DiskMultipolygonManager(osmium::area::Assembler::config_type config, osmium::TagsFilter filter,
                                                 std::filesystem::path ways_file)
    : m_config(config), m_filter(std::move(filter)), m_ways_out(std::move(ways_file)) {}

DiskMultipolygonManager::~DiskMultipolygonManager() = default;

// MultipolygonManager::new_relation(): type=multipolygon or type=boundary, a tag the filter
// wants, at least one way member.
bool DiskMultipolygonManager::wanted(const osmium::Relation& relation) const {
    const char* type = relation.tags().get_value_by_key("type");
    if (type == nullptr) return false;
    if ((std::strcmp(type, "multipolygon") != 0 && std::strcmp(type, "boundary") != 0) ||
        !osmium::tags::match_any_of(relation.tags(), m_filter)) {
        return false;
    }
    return std::any_of(relation.members().cbegin(), relation.members().cend(),
                       [](const osmium::RelationMember& m) { return m.type() == osmium::item_type::way; });
}

// RelationsManager::relation(): a copy of the relation in which only way members keep their id.
void DiskMultipolygonManager::relation(const osmium::Relation& relation) {
    if (!wanted(relation)) return;
    const std::size_t offset = m_relations.committed();
    m_relations.add_item(relation);
    m_relations.commit();
    auto& copy = m_relations.get<osmium::Relation>(offset);
    const std::size_t index = m_relation_offsets.size();
    m_relation_offsets.push_back(offset);
    m_missing.push_back(0);
    std::size_t n = 0;
    for (auto& member : copy.members()) {
        if (member.type() == osmium::item_type::way) {
            m_members.push_back({member.ref(), n, index});
            ++m_missing[index];
        } else {
            member.set_ref(0);
        }
        ++n;
    }
}

void DiskMultipolygonManager::prepare_for_lookup() { std::sort(m_members.begin(), m_members.end()); }

DiskMultipolygonManager::SecondPass& DiskMultipolygonManager::handler(
    const std::function<void(osmium::memory::Buffer&&)>& callback) {
    m_output.set_callback(callback);
    return m_second_pass;
}

// RelationsManager::handle_way() with MembersDatabase::add(): the way is kept (here: written to
// the file) once for all its relations; each relation it completes is made into an area.
void DiskMultipolygonManager::handleWay(const osmium::Way& way) {
    const auto range = std::equal_range(m_members.begin(), m_members.end(), Member{way.id(), 0, 0},
                                        [](const Member& a, const Member& b) { return a.way_id < b.way_id; });
    if (range.first != range.second) {
        const std::uint64_t at = m_ways_out.append(
            std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(way.data()),  // NOLINT: item bytes
                                          way.byte_size()));
        ++m_member_ways;
        for (auto it = range.first; it != range.second; ++it) it->spill = at;
        for (auto it = range.first; it != range.second; ++it) {
            if (--m_missing[it->relation] == 0) {
                completeRelation(it->relation);
                m_output.possibly_flush();
            }
        }
    }
    afterWay(way);
    m_output.possibly_flush();
}

// MultipolygonManager::complete_relation(), its member ways read back from the file.
void DiskMultipolygonManager::completeRelation(std::size_t index) {
    const auto& relation = m_relations.get<osmium::Relation>(m_relation_offsets[index]);
    if (m_ways_out.bytes() > m_flushed) {
        m_ways_out.flush();
        m_flushed = m_ways_out.bytes();
        if (!m_ways_in) m_ways_in = std::make_unique<SpillReader>(m_ways_out.path());
        m_ways_in->refresh();
    }
    osmium::memory::Buffer ways{1 << 16, osmium::memory::Buffer::auto_grow::yes};
    std::vector<std::size_t> offsets;
    std::vector<std::uint8_t> record;
    for (const auto& member : relation.members()) {
        if (member.ref() == 0) continue;
        const auto it = std::lower_bound(m_members.begin(), m_members.end(), Member{member.ref(), 0, 0},
                                         [](const Member& a, const Member& b) { return a.way_id < b.way_id; });
        m_ways_in->readAt(it->spill, record);
        offsets.push_back(ways.committed());
        ways.add_item(*reinterpret_cast<const osmium::memory::Item*>(record.data()));  // NOLINT: item bytes
        ways.commit();
    }
    std::vector<const osmium::Way*> members;
    members.reserve(offsets.size());
    for (const std::size_t o : offsets) members.push_back(&ways.get<osmium::Way>(o));
    try {
        osmium::area::Assembler assembler{m_config};
        assembler(relation, members, m_output.buffer());
    } catch (const osmium::invalid_location&) {
        // as MultipolygonManager: the relation gives no area
    }
    ++m_complete;
}

// MultipolygonManager::after_way(): a closed way with a wanted tag is an area of its own.
void DiskMultipolygonManager::afterWay(const osmium::Way& way) {
    if (way.nodes().size() <= 3) return;
    try {
        if (!way.nodes().front().location() || !way.nodes().back().location()) {
            throw osmium::invalid_location{"invalid location"};
        }
        if (way.ends_have_same_location()) {
            if (way.tags().has_tag("area", "no")) return;
            if (osmium::tags::match_none_of(way.tags(), m_filter)) return;
            osmium::area::Assembler assembler{m_config};
            assembler(way, m_output.buffer());
            m_output.possibly_flush();
        }
    } catch (const osmium::invalid_location&) {
        // as MultipolygonManager: the way gives no area
    }
}

}  // namespace navmap::map::detail
