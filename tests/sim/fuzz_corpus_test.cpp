// SPDX-License-Identifier: Apache-2.0
// Runs the navmap-sim place-parser fuzz entry (tests/fuzz/sim_place_fuzz.cpp) on broken inputs.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_corpus.h"

int navmapFuzzSimPlace(const std::uint8_t* data, std::size_t size);

namespace {

TEST(SimFuzzCorpus, PlaceParserSurvivesBrokenInputs) {
    std::vector<std::string> corpus = {
        "",
        ",",
        ",,",
        "1,",
        ",1",
        "1e308,1e308",
        "-1e-320,5",
        "nan,nan",
        "inf,-inf",
        "0x10,0x20",
        "+,-",
        "42.5,1.5,",
        "  ,  ",
        std::string("\0,\0", 3),
        "\xC3",
        "\xC3\xC3\xC3",
        "\xFF\xFE",
        "la la la la",
        "l'",
        "'",
        "-",
        "Sant Juli\xC3",
        std::string(10000, 'a'),
        std::string(5000, ','),
        "42,5.1.2",
        "999999999999999999999999,1",
        "1,999999999999999999999",
        "les",
        "\xC2\xB7\xC2\xB7",
    };
    for (int i = 0; i < 256; ++i) corpus.push_back(std::string(1, static_cast<char>(i)) + "Encamp");
    for (const auto& c : corpus) {
        EXPECT_EQ(navmapFuzzSimPlace(reinterpret_cast<const std::uint8_t*>(c.data()), c.size()), 0);
    }
}

// Every file of the checked-in libFuzzer corpus (tests/fuzz/corpus/sim_place).
TEST(SimFuzzCorpus, CheckedInCorpus) {
    EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzSimPlace, "sim_place"), 20U);
}

}  // namespace
