// SPDX-License-Identifier: Apache-2.0
// Runs the fuzz entry points (tests/fuzz/*_fuzz.cpp) on a corpus of broken inputs, so the normal
// suite exercises them: every prefix and byte-flipped copy of data/navmap.dbc and of a small
// candump log, plus hand-written nasties.

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "fuzz_corpus.h"
#include "test_paths.h"

int navmapFuzzDbc(const std::uint8_t* data, std::size_t size);
int navmapFuzzCandump(const std::uint8_t* data, std::size_t size);

namespace {

std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

template <typename Fn>
void runCorpus(const std::string& seed, const std::vector<std::string>& extra, Fn fn) {
    const auto run = [&](const std::string& s) { fn(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()); };
    for (std::size_t n = 0; n <= seed.size(); n += 3) {
        run(seed.substr(0, n));
    }
    std::mt19937 rng(42);
    for (int i = 0; i < 300; ++i) {
        std::string s = seed;
        for (int k = 0; k < 4; ++k) {
            s[rng() % s.size()] = static_cast<char>(rng());
        }
        run(s);
    }
    for (const auto& e : extra) {
        run(e);
    }
}

}  // namespace

TEST(FuzzCorpus, DbcParserSurvivesBrokenInputs) {
    const std::string seed = readFile(navmap::test::dataDir() / "navmap.dbc");
    ASSERT_GT(seed.size(), 500U);
    const std::vector<std::string> extra = {
        std::string("\0\0\0BO_ 1 A: 8 X\n", 16),
        "BO_ 4294967295 A: 64 X\n SG_ S : 511|64@0- (1e308,-1e308) [1|-1] \"\" X\n",
        "BO_ 1 A: 64 X\n SG_ S : 0|64@1- (nan,inf) [nan|inf] \"\" X\n",
        "BO_ 1 A: 8 X\n SG_ S m99999999999 : 0|8@1+ (1,0) [0|0] \"\" X\n",
        // NOLINTNEXTLINE(bugprone-suspicious-missing-comma): one input, split over two lines
        "BO_ 1 A: 8 X\n SG_ S M : 0|64@1+ (1,0) [0|0] \"\" X\n SG_ T m18446744073709551615 : 0|8@1+ (1,0) [0|0] \"\" "
        "X\n",
        "CM_ \"\\\"\n\n\n",
        std::string(10000, '"'),
        "VAL_ 1 S 1 \"a\" 2 \"b\" 3",
        "SIG_VALTYPE_ 1 S : 9;",
        "BO_ 1 A: 8 X\n SG_ S : 0|32@1+ (1,0) [0|0] \"\" X\nSIG_VALTYPE_ 1 S : 1;\n",
    };
    runCorpus(seed, extra, navmapFuzzDbc);
    SUCCEED();
}

TEST(FuzzCorpus, CandumpReaderSurvivesBrokenInputs) {
    const std::string seed =
        "(1487342025.615950) can0 187#E21408C800100300\n"
        "(1484869955.91) can1 091#7ef47ef424f1f000\n"
        "(1.0) vcan0 1ABCDEF0##3001122334455667788990011\n"
        "(1.0) vcan0 123#R4\n"
        "(1.0) vcan0 20000004#0004000000000000 R\n";
    const std::vector<std::string> extra = {
        std::string("(1.0) can0 123#\0\0", 17),
        "(99999999999999999999999.9) can0 123#00\n",
        "(1.9999999999999999999999) can0 123#00\n",
        "((((((\n))))))\n",
        "(1.0) can0 123##F" + std::string(200, 'F') + "\n",
        "(1.0) can0 FFFFFFFF#00\n(1.0) can0 DFFFFFFF#0000000000000000\n",
        std::string(100000, '\n'),
    };
    runCorpus(seed, extra, navmapFuzzCandump);
    SUCCEED();
}

// The checked-in libFuzzer corpora (tests/fuzz/corpus/{dbc,candump}, tests/fuzz/seeds/dbc): an
// entry that crashes the parser fails here, without clang.
TEST(FuzzCorpus, DbcCheckedInCorpus) { EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzDbc, "dbc"), 20U); }

TEST(FuzzCorpus, CandumpCheckedInCorpus) {
    EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzCandump, "candump"), 20U);
}
