// SPDX-License-Identifier: Apache-2.0
// Runs the libFuzzer entry of tests/fuzz/text_shape_fuzz.cpp on broken and hostile label text.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_corpus.h"
#include "navmap/render/text/font_collection.h"

int navmapFuzzTextShape(const std::uint8_t* data, std::size_t size);

TEST(TextFuzzCorpus, BadInputsNeverCrash) {
    if (navmap::render::text::debianFontFiles().regular.empty()) GTEST_SKIP() << "needs fonts-dejavu-core";
    std::vector<std::string> corpus = {
        "", std::string(1, '\0'), std::string("Ordi\0no", 7),
        "\xC3",                  // truncated 2-byte sequence
        "\xE4\xB8",              // truncated CJK
        "\xF8\x88\x80\x80\x80",  // 5-byte form
        "\xC0\xAF",              // overlong '/'
        "\xED\xA0\x80",          // surrogate
        "\xF4\x90\x80\x80",      // above U+10FFFF
        // NOLINTNEXTLINE(bugprone-suspicious-missing-comma): one input, a BOM then "BOM"
        "\xEF\xBB\xBF"
        "BOM",
        "a\xCC\x80\xCC\x80\xCC\x80\xCC\x80\xCC\x80\xCC\x80\xCC\x80\xCC\x80",  // stacked combining marks
        "\xE2\x80\xAE"
        "RTL override \xD7\xA9\xD7\x9C\xD7\x95\xD7\x9D",  // bidi + Hebrew
        "\xF0\x9F\x91\xA8\xE2\x80\x8D\xF0\x9F\x91\xA9",   // emoji ZWJ sequence
        "\t\n\r\x7F", std::string(3000, 'W'),             // long: overflows the small fuzz atlas
    };
    std::string all_cjk;
    for (char32_t cp = 0x4E00; cp < 0x4E00 + 300; ++cp) {  // many distinct glyphs: eviction
        all_cjk += static_cast<char>(0xE0 | (cp >> 12));
        all_cjk += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
        all_cjk += static_cast<char>(0x80 | (cp & 0x3F));
    }
    corpus.push_back(all_cjk);
    for (int round = 0; round < 2; ++round) {
        for (const std::string& s : corpus) {
            EXPECT_EQ(navmapFuzzTextShape(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), 0);
        }
    }
}

// Every file of the checked-in libFuzzer corpus (tests/fuzz/corpus/text_shape).
TEST(TextFuzzCorpus, CheckedInCorpus) {
    if (navmap::render::text::debianFontFiles().regular.empty()) GTEST_SKIP() << "needs fonts-dejavu-core";
    EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzTextShape, "text_shape"), 20U);
}
