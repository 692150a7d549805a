// SPDX-License-Identifier: Apache-2.0
#pragma once
// A small deterministic random generator (SplitMix64) for the orthoimage pipeline: scrambling,
// training, vegetation and fields must give the same result on every platform and standard
// library, which std::uniform_*_distribution does not promise.

#include <cstdint>

namespace navmap::map::ortho {

class Rng {
public:
    explicit Rng(std::uint64_t seed) : m_state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
    /// Uniform in [lo, hi).
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    /// Uniform integer in [0, n), n > 0.
    std::uint64_t below(std::uint64_t n) { return next() % n; }

private:
    std::uint64_t m_state;
};

/// Mixes values into a seed (tile ids, indices) so that streams do not repeat across tiles.
inline std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b) {
    Rng r(a ^ (b * 0x9e3779b97f4a7c15ULL));
    return r.next();
}

}  // namespace navmap::map::ortho
