// SPDX-License-Identifier: Apache-2.0
#pragma once
// Strict UTF-8 decoding for label text. Private to render/src/text.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace navmap::render::text {

struct DecodedChar {
    char32_t codepoint = 0;
    std::uint32_t offset = 0;  ///< byte offset of the sequence
    std::uint32_t length = 0;  ///< bytes consumed (>= 1)
    bool valid = true;         ///< false: malformed, codepoint is U+FFFD
};

/// Decodes the whole string. Overlong forms, surrogates, values above U+10FFFF and truncated
/// sequences decode as U+FFFD consuming one byte (WHATWG "maximal subpart" simplified).
std::vector<DecodedChar> decodeUtf8(std::string_view text);

}  // namespace navmap::render::text
