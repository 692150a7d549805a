// SPDX-License-Identifier: Apache-2.0
#pragma once
// The GLSL ES sources of shaders/, embedded at build time (cmake/EmbedShaders.cmake).
// Only render/ includes this header.

#include <span>
#include <string_view>

namespace navmap::shaders {

/// One shader stage file: its file name in shaders/ and its text.
struct ShaderSource {
    std::string_view name;
    std::string_view text;
};

/// Every embedded shader, in the order CMake listed them.
std::span<const ShaderSource> all();

}  // namespace navmap::shaders
