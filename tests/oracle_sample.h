#pragma once

// How densely the brute-force oracle tests sample their scenes.
//
// The oracle tests compare a fast query with an exhaustive one (every triangle pair, every
// candidate crossing) on many rays, vertices, poses or steps. The Release suite runs them in full:
// it is where their answers are checked on the whole sample. The sanitizer build runs the same
// tests to find memory errors and undefined behaviour, which show on any sample that runs through
// the same code paths, at 5-20 times the cost per query. There (CMake option
// HIPFAI_THIN_ORACLE_TESTS, on with HIPFAI_SANITIZE) each such test keeps every
// `kOracleThinning`-th ray, vertex, pose or step of its sample, and keeps every kind of case its
// full sample holds (each scene, table size, mapping and hard configuration still runs).

#ifndef HIPFAI_ORACLE_THINNING
#define HIPFAI_ORACLE_THINNING 1
#endif

namespace hipfai::test {

/// 1 in the full suite; k > 1: the oracle tests keep every k-th item of their samples.
inline constexpr int kOracleThinning = HIPFAI_ORACLE_THINNING;
static_assert(kOracleThinning >= 1);

/// Whether the oracle tests run thinned samples (the sanitizer build).
inline constexpr bool kOracleSamplesThinned = kOracleThinning > 1;

}  // namespace hipfai::test
