#pragma once
// Runs a libFuzzer entry point over a deterministic corpus of broken inputs in a plain test:
// every prefix of each good seed, copies of each seed with three random bytes changed, and
// hand-written nasties. A crash, sanitizer report or hang fails the test.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace navmap::test {

using FuzzEntry = int (*)(const std::uint8_t* data, std::size_t size);

/// Returns how many inputs ran.
std::size_t runFuzzCorpus(FuzzEntry entry, const std::vector<std::string>& seeds, const std::vector<std::string>& extra,
                          int flipped_copies_per_seed);

}  // namespace navmap::test
