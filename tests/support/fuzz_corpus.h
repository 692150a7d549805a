// SPDX-License-Identifier: Apache-2.0
#pragma once
// Runs a libFuzzer entry point in a plain test, so the normal (gcc) suite catches what the fuzzers
// would: a deterministic corpus of broken inputs (every prefix of each good seed, copies of each
// seed with three random bytes changed, hand-written nasties), and the checked-in corpus of a
// fuzz target (tests/fuzz/corpus/<target>, tests/fuzz/seeds/<target>). A crash, sanitizer report
// or hang fails the test.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace navmap::test {

using FuzzEntry = int (*)(const std::uint8_t* data, std::size_t size);

/// Returns how many inputs ran.
std::size_t runFuzzCorpus(FuzzEntry entry, const std::vector<std::string>& seeds, const std::vector<std::string>& extra,
                          int flipped_copies_per_seed);

/// Runs `entry` once on every file of tests/fuzz/corpus/<target> and tests/fuzz/seeds/<target>
/// (sorted by path). Each file's path goes to stderr before it runs, so the output of a crashed
/// test names the input. Returns how many files ran.
std::size_t runCheckedInCorpus(FuzzEntry entry, std::string_view target);

}  // namespace navmap::test
