// SPDX-License-Identifier: Apache-2.0
// GCC 12 reports a false -Wstringop-overread inside libosmium's builder once it is inlined here,
// as in compile_read.cpp (osmium/builder/osm_object_builder.hpp reads a NUL-terminated user name).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif

#include "osm_limits.h"

#include <osmium/builder/osm_object_builder.hpp>

#include <algorithm>

#include "navmap/map/compile/compiler.h"

namespace navmap::map::detail {

void OsmLimits::way(const osmium::Way& way) const {
    const std::size_t n = way.nodes().size();
    if (n <= kMaxWayNodes) return;
    throw CompileError(m_source + ": way " + std::to_string(way.id()) + " has " + std::to_string(n) +
                       " node references, more than " + std::to_string(kMaxWayNodes) +
                       " (OpenStreetMap allows 2000 per way)");
}

const osmium::Relation& OsmLimits::uniqueMembers(const osmium::Relation& relation) {
    const auto& members = relation.members();
    const std::size_t n = members.size();
    if (n > kMaxRelationMembers) {
        throw CompileError(m_source + ": relation " + std::to_string(relation.id()) + " has " + std::to_string(n) +
                           " members, more than " + std::to_string(kMaxRelationMembers) +
                           " (OpenStreetMap allows 32000 per relation)");
    }
    // Sorted (type, id) pairs: a repeat is a neighbour equal to its predecessor, in n log n.
    m_seen.clear();
    for (const auto& m : members) m_seen.emplace_back(static_cast<int>(m.type()), m.ref());
    std::sort(m_seen.begin(), m_seen.end());
    const auto unique_end = std::unique(m_seen.begin(), m_seen.end());
    const auto repeats = static_cast<std::uint64_t>(m_seen.end() - unique_end);
    if (repeats == 0) return relation;
    m_seen.erase(unique_end, m_seen.end());
    if (m_relations_with_repeats++ == 0) m_first_with_repeats = relation.id();
    m_repeated += repeats;

    // The copy: the relation's attributes and tags, each member at its first place.
    std::vector<bool> taken(m_seen.size(), false);
    m_copy.clear();
    {
        osmium::builder::RelationBuilder builder{m_copy};
        builder.set_id(relation.id())
            .set_version(relation.version())
            .set_changeset(relation.changeset())
            .set_timestamp(relation.timestamp())
            .set_uid(relation.uid())
            .set_visible(relation.visible())
            .set_user(relation.user());
        builder.add_item(relation.tags());
        osmium::builder::RelationMemberListBuilder list{builder};
        for (const auto& m : members) {
            const std::pair<int, std::int64_t> key{static_cast<int>(m.type()), m.ref()};
            const auto at =
                static_cast<std::size_t>(std::lower_bound(m_seen.begin(), m_seen.end(), key) - m_seen.begin());
            if (taken[at]) continue;
            taken[at] = true;
            list.add_member(m.type(), m.ref(), m.role());
        }
    }
    m_copy.commit();
    return m_copy.get<osmium::Relation>(0);
}

}  // namespace navmap::map::detail
