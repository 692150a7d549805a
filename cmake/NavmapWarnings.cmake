# SPDX-License-Identifier: Apache-2.0
# One INTERFACE target carries the warning and sanitizer flags; every navmap target links it.
add_library(navmap_warnings INTERFACE)
target_compile_options(navmap_warnings INTERFACE -Wall -Wextra -Wpedantic)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(navmap_warnings INTERFACE -Wshadow=local)  # gcc only
endif()
if(NAVMAP_WITH_WERROR)
  target_compile_options(navmap_warnings INTERFACE -Werror)
endif()
if(NAVMAP_WITH_ASAN)
  target_compile_options(navmap_warnings INTERFACE -fsanitize=address -fno-omit-frame-pointer)
  target_link_options(navmap_warnings INTERFACE -fsanitize=address)
endif()
if(NAVMAP_WITH_UBSAN)
  target_compile_options(navmap_warnings INTERFACE -fsanitize=undefined -fno-sanitize-recover=undefined)
  target_link_options(navmap_warnings INTERFACE -fsanitize=undefined)
endif()
# Fuzz build (NAVMAP_WITH_FUZZ with clang): every navmap target carries libFuzzer's coverage
# instrumentation and ASan/UBSan, so the fuzzers in tests/fuzz see the project code they drive
# (decoders, parsers, the text shaper glue), not just their own entry points. The fuzz targets
# stop at the first UBSan report (tests/fuzz/fuzz_sanitizer_options.cpp). System libraries
# (HarfBuzz, FreeType, zlib) stay uninstrumented. Build only the fuzzers in such a tree:
# --target navmap_fuzz.
if(NAVMAP_WITH_FUZZ AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  target_compile_options(navmap_warnings INTERFACE -fsanitize=fuzzer-no-link,address,undefined
      -fno-omit-frame-pointer)
  target_link_options(navmap_warnings INTERFACE -fsanitize=address,undefined)
endif()
