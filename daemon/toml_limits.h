// SPDX-License-Identifier: Apache-2.0
#pragma once
// A pass over TOML text before toml++ parses it: how deep tables, dotted keys, inline tables and
// arrays nest, and how many keys, table headers and array elements there are. toml++ recurses
// once per level of a dotted key or table header and builds every value it reads, so a 400 KB
// file of one 200,000-level header crashed it (stack overflow) and a file of a million
// [[profile]] tables took 1.2 GB; this pass refuses such text first, in constant memory and one
// pass over the text, whoever read the file (docs/navmapd.md "Configuration limits").
// It checks no syntax: toml++ does that afterwards on text that passed.

#include <cstddef>
#include <string>
#include <string_view>

namespace navmap::daemon {

struct TomlLimits {
    /// Levels of tables, dotted-key parts, inline tables and arrays, counted together: `[a.b]` is
    /// 2, `c.d = [{e = 1}]` under it reaches 6 (the array 5, the inline table's key 6).
    std::size_t max_depth = 32;
    /// Keys, table headers and array elements of the whole file.
    std::size_t max_values = 20000;
};

/// Empty when `text` stays within `limits`; otherwise "<source>:<line>:<column>: <problem>" at the
/// first place that goes beyond them.
std::string checkTomlLimits(std::string_view text, std::string_view source_name, const TomlLimits& limits = {});

}  // namespace navmap::daemon
