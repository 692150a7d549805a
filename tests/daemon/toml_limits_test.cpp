// SPDX-License-Identifier: Apache-2.0
// The pass over configuration text before toml++ parses it (daemon/toml_limits.h): deep tables,
// dotted keys, inline tables and arrays and too many values are refused with the place and the
// reason, before toml++ would recurse or allocate; everything TOML hides in strings and comments
// is not counted, and the limits are exact.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "config.h"
#include "fuzz_corpus.h"
#include "toml_limits.h"

int navmapFuzzConfig(const std::uint8_t* data, std::size_t size);

namespace {

using namespace navmap::daemon;

constexpr const char* kDeep =
    "nested more than 32 levels deep (tables, dotted keys, arrays and inline tables together)";

std::string repeat(const std::string& s, std::size_t n) {
    std::string out;
    out.reserve(s.size() * n);
    for (std::size_t i = 0; i < n; ++i) out += s;
    return out;
}

// "a.a. ... .a": a dotted key of n parts.
std::string dotted(std::size_t n) { return repeat("a.", n - 1) + "a"; }

std::string parseError(const std::string& text) {
    ConfigError err;
    EXPECT_FALSE(parseConfig(text, "navmapd.toml", &err));
    return err.message;
}

// The files: 200,000 levels of one header or one dotted key took toml++ down (SIGSEGV);
// inline tables and arrays go through the same limit.
TEST(TomlLimits, DeepHeadersKeysInlineTablesAndArraysAreRefusedBeforeParsing) {
    for (const std::size_t n : {33u, 1000u, 200000u, 1000000u}) {
        EXPECT_EQ(parseError("[" + dotted(n) + "]\n"), std::string("navmapd.toml:1:2: table header ") + kDeep) << n;
        EXPECT_EQ(parseError("[[" + dotted(n) + "]]\n"), std::string("navmapd.toml:1:3: table header ") + kDeep) << n;
        EXPECT_EQ(parseError("# a comment\n" + dotted(n) + " = 1\n"), std::string("navmapd.toml:2:1: key ") + kDeep)
            << n;
    }
    // Under a header, a dotted key adds to its depth: 2 + 31 parts.
    EXPECT_EQ(parseError("[store]\n\n[render.x]\n" + dotted(31) + " = 1\n"),
              std::string("navmapd.toml:4:1: key ") + kDeep);
    // Arrays and inline tables: the one that opens level 33 is named, at its column (a = is
    // level 1, each array one more).
    EXPECT_EQ(parseError("a = " + repeat("[", 200000) + repeat("]", 200000) + "\n"),
              std::string("navmapd.toml:1:36: array ") + kDeep);
    EXPECT_EQ(parseError("a = " + repeat("[", 31) + "{}" + repeat("]", 31) + "\n"),
              std::string("navmapd.toml:1:36: inline table ") + kDeep);
    // {b = {b = ...}}: the 16th table's key is level 33.
    EXPECT_EQ(parseError("a = " + repeat("{b = ", 200000) + "1" + repeat("}", 200000) + "\n"),
              std::string("navmapd.toml:1:81: key ") + kDeep);
    // Keys inside inline tables count their parts too, also over several lines of an array.
    EXPECT_EQ(parseError("a = [\n  1,\n  {" + dotted(40) + " = 2},\n]\n"),
              std::string("navmapd.toml:3:4: key ") + kDeep);
}

TEST(TomlLimits, TheLimitsAreExact) {
    EXPECT_EQ(checkTomlLimits("[" + dotted(32) + "]\n", "f"), "");
    EXPECT_NE(checkTomlLimits("[" + dotted(33) + "]\n", "f"), "");
    EXPECT_EQ(checkTomlLimits("[a.b]\n" + dotted(30) + " = 1\n", "f"), "");
    EXPECT_NE(checkTomlLimits("[a.b]\n" + dotted(31) + " = 1\n", "f"), "");
    // a = [[...]]: the key is level 1, each array one more.
    EXPECT_EQ(checkTomlLimits("a = " + repeat("[", 31) + repeat("]", 31), "f"), "");
    EXPECT_NE(checkTomlLimits("a = " + repeat("[", 32) + repeat("]", 32), "f"), "");
    EXPECT_EQ(checkTomlLimits("a = " + repeat("{b = ", 15) + "1" + repeat("}", 15), "f"), "");  // 1 + 2 * 15
    EXPECT_NE(checkTomlLimits("a = " + repeat("{b = ", 16) + "1" + repeat("}", 16), "f"), "");
    // Values: keys, headers and array elements together.
    const TomlLimits small{32, 8};
    EXPECT_EQ(checkTomlLimits("[t]\na = [1, 2, 3]\nb = {c = 1, d = 2}\n", "f", small), "");  // 8
    EXPECT_EQ(checkTomlLimits("[t]\na = [1, 2, 3]\nb = {c = 1, d = 2}\n[u]\n", "f", small),
              "f:4:2: more than 8 keys, tables and array elements");
}

// Brackets, braces and dots inside strings and comments are text, not structure: a string of a
// million '[' passes, in each of TOML's four kinds of string and in quoted keys.
TEST(TomlLimits, StringsAndCommentsAreNotStructure) {
    const std::string brackets = repeat("[{.", 100000);
    for (const std::string& text : {
             "a = \"" + brackets + "\"\n", "a = '" + brackets + "'\n",
             "a = \"\"\"\n" + brackets + "\n" + brackets + "\"\"\"\n", "a = '''\n" + brackets + "\n'''\n",
             "a = \"x\\\"" + brackets + "\"\n",  // an escaped quote does not end the string
             "# " + brackets + "\na = 1 # " + brackets + "\n", "\"" + dotted(1000) + "\" = 1\n",
             "['" + dotted(1000) + "'.b]\n",
             std::string("a = \"\"\"x\"\"\"\"\"\nb = [1]\n"),  // """x""""" is x"" and ends there
         }) {
        EXPECT_EQ(checkTomlLimits(text, "f"), "") << text.substr(0, 60);
    }
    // A string that is not closed on its line ends there: the next line is read as TOML again.
    EXPECT_EQ(checkTomlLimits("a = \"open\nb = " + repeat("[", 40) + "\n", "f"),
              "f:2:" + std::to_string(5 + 31) + ": array " + kDeep);
}

// A million [[profile]] tables passed --check-config at 1.2 GB; past the value limit they are
// refused before parsing, and beyond 64 profiles after it.
TEST(TomlLimits, ProfilesAreCapped) {
    EXPECT_EQ(parseError(repeat("[[profile]]\n", 1000000)),
              "navmapd.toml:20001:3: more than 20000 keys, tables and array elements");
    std::string text;
    for (std::size_t i = 0; i <= kMaxProfiles; ++i) text += "[[profile]]\nname = \"p" + std::to_string(i) + "\"\n";
    EXPECT_EQ(parseError(text), "navmapd.toml:129:1: 65 profiles, more than 64");
    text.resize(text.rfind("[[profile]]"));
    ConfigError err;
    const auto c = parseConfig(text, "navmapd.toml", &err);
    ASSERT_TRUE(c) << err.message;
    EXPECT_EQ(c->profiles.size(), kMaxProfiles);
}

// The shipped configuration and the signal maps of the tree stay well inside: a quarter of the
// depth and a hundredth of the values.
TEST(TomlLimits, TheShippedFilesPass) {
    for (const char* file : {"/daemon/navmapd.toml", "/tests/ipc/data/ford_fusion_signals.toml"}) {
        std::ifstream in(std::string(NAVMAP_SOURCE_DIR) + file);
        ASSERT_TRUE(in) << file;
        const std::string text{std::istreambuf_iterator<char>(in), {}};
        EXPECT_EQ(checkTomlLimits(text, file, TomlLimits{8, 200}), "");
    }
}

// The fuzz entry (tests/fuzz/config_fuzz.cpp) on every prefix and byte-changed copy of the
// shipped file, on hostile files, and on the checked-in corpus: the pass answers and toml++
// never goes down on what it lets through.
TEST(TomlLimits, FuzzEntryOnBrokenAndHostileFiles) {
    std::ifstream in(std::string(NAVMAP_SOURCE_DIR) + "/daemon/navmapd.toml");
    const std::string shipped{std::istreambuf_iterator<char>(in), {}};
    ASSERT_GT(shipped.size(), 1000u);
    const std::vector<std::string> extra = {
        "[" + dotted(100000) + "]",           dotted(100000) + " = 1",
        "a = " + repeat("[", 100000),         "a = " + repeat("{b = ", 100000),
        "a = [" + repeat("{a = [", 50000),    "[[" + dotted(32) + "]]\n" + dotted(1) + " = " + repeat("[", 40),
        repeat("[[profile]]\n", 30000),       "a = \"\"\"" + repeat("[", 1000),
        "a = '''\n" + repeat("{", 1000),      std::string("\0[\0a\0.\0b]\0", 10),
        "\"" + repeat("\\", 1001) + "\" = 1",
    };
    EXPECT_GT(navmap::test::runFuzzCorpus(navmapFuzzConfig, {shipped}, extra, 300), 2000u);
}

TEST(TomlLimits, FuzzEntryOnCheckedInCorpus) {
    EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzConfig, "config"), 7u);
}

}  // namespace
