// SPDX-License-Identifier: Apache-2.0
#pragma once
// The caps on single OpenStreetMap objects in navmap-compile (docs/tile-store.md "Limits"): a way
// of 4 million node references in a 4 KB file took the compile to 714 MB (442 MB with
// --memory-limit 64), and a multipolygon relation listing one closed way 200,000 times took the
// in-memory assembly 32 s, growing with the square of the count. A way or a relation beyond its
// cap stops the compile with an error that names it, before any handler copies it; a relation
// that lists a member more than once reaches the multipolygon assembly with each member once.
// Private to navmap_map.

#include <osmium/handler.hpp>
#include <osmium/memory/buffer.hpp>
#include <osmium/osm/relation.hpp>
#include <osmium/osm/way.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace navmap::map::detail {

/// Node references of one way: OpenStreetMap's API allows 2,000; fifty times that.
inline constexpr std::size_t kMaxWayNodes = 100000;
/// Members of one relation: OpenStreetMap's API allows 32,000; three times that.
inline constexpr std::size_t kMaxRelationMembers = 100000;

class OsmLimits : public osmium::handler::Handler {
public:
    /// `source_name`: the input file, named in the errors.
    explicit OsmLimits(std::string source_name) : m_source(std::move(source_name)) {}

    /// First handler of the pass that reads ways: throws CompileError "<file>: way <id> has <n>
    /// node references, more than <cap> ..." for a way beyond kMaxWayNodes.
    void way(const osmium::Way& way) const;

    /// The relations pass, in front of the multipolygon managers: throws CompileError for a
    /// relation beyond kMaxRelationMembers; returns `relation` itself, or, when it lists an
    /// object more than once, a copy that lists each once (its first place and role), valid until
    /// the next call.
    const osmium::Relation& uniqueMembers(const osmium::Relation& relation);

    /// Members dropped as repeats, the relations they were dropped from, and the first of those.
    [[nodiscard]] std::uint64_t repeatedMembers() const { return m_repeated; }
    [[nodiscard]] std::uint64_t relationsWithRepeats() const { return m_relations_with_repeats; }
    [[nodiscard]] std::int64_t firstRelationWithRepeats() const { return m_first_with_repeats; }

private:
    std::string m_source;
    osmium::memory::Buffer m_copy{1024, osmium::memory::Buffer::auto_grow::yes};
    std::vector<std::pair<int, std::int64_t>> m_seen;  // (type, id) of the members, sorted
    std::uint64_t m_repeated = 0, m_relations_with_repeats = 0;
    std::int64_t m_first_with_repeats = 0;
};

}  // namespace navmap::map::detail
