// SPDX-License-Identifier: Apache-2.0
// Runs the control fuzz entry point (tests/fuzz/control_fuzz.cpp) on a corpus of broken lines:
// every prefix and byte-flipped copy of valid requests, plus hand-written nasties.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fuzz_corpus.h"

int navmapFuzzControl(const std::uint8_t* data, std::size_t size);

TEST(ControlFuzzCorpus, ParserSurvivesBrokenLines) {
    const std::vector<std::string> seeds = {
        R"({"cmd":"set_route","id":"r1","points":[[42.5075,1.5218],[42.51,1.53]],"maneuvers":[{"index":1,"type":"turn_left","text":"CG-2"}]})",
        R"({"cmd":"set_view","display":"cluster","mode":"snail","orientation":"north-up","id":"x"})",
        R"({"cmd":"subscribe","events":["route_progress","position_lost"]})",
        R"({"cmd":"set_style","style":"night"})",
    };
    const std::vector<std::string> extra = {
        "",
        "{",
        "}",
        "[]",
        "null",
        "1e400",
        "-0",
        "\"\\ud800\"",
        std::string(5000, '['),
        std::string(5000, '{'),
        std::string("{\"cmd\":\"set_route\",\"id\":\"\0\",\"points\":[[0,0],[0,0]]}", 48),
        R"({"cmd":"set_route","id":"r","points":[[1e308,1e308],[-1e308,5]]})",
        R"({"cmd":"set_route","id":"r","points":[[0,0],[0,0]],"maneuvers":[{"index":18446744073709551615,"type":"exit"}]})",
        R"({"cmd":"set_route","id":"r","points":[[0,0],[0,0]],"maneuvers":[{"index":-9223372036854775808,"type":"exit"}]})",
        R"({"cmd":"set_style","style":"night","style":"day"})",
        "{\"cmd\":\"set_view\",\"display\":\"" + std::string(1000, '\xc3') + "\",\"mode\":\"bird\"}",
        "{\"cmd\":\"" + std::string(300, 'z') + "\"}",
    };
    const std::size_t runs = navmap::test::runFuzzCorpus(navmapFuzzControl, seeds, extra, 300);
    EXPECT_GT(runs, 1500U);
}

// Every file of the checked-in libFuzzer corpus (tests/fuzz/corpus/control).
TEST(ControlFuzzCorpus, CheckedInCorpus) {
    EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzControl, "control"), 20U);
}
