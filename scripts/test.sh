#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The test command: installs what is missing, builds everything with warnings as errors, and
# runs the CTest suite. Exits non-zero on any failure. Long soak runs, the cross build, lint and the
# Slurm cluster are opt-in:
#   scripts/test.sh            everything except the labels 'soak', 'cross', 'arm64', 'lint' and 'slurm'
#   NAVMAP_TEST_ARGS="-L soak" scripts/test.sh     only the soak tests
#   NAVMAP_TEST_ARGS="-L cross" scripts/test.sh    the aarch64 cross build of the client library
#   NAVMAP_TEST_ARGS="-L arm64" scripts/test.sh    everything built for aarch64 and run under qemu
#   NAVMAP_TEST_ARGS="-L lint" scripts/test.sh     clang-tidy over the tree (scripts/lint.sh, ~1 h)
#   NAVMAP_TEST_ARGS="-L slurm" scripts/test.sh    the sharded compile on a private Slurm cluster
#                                                  (scripts/slurm-local.sh installs slurm-wlm, munge)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
scripts/install-deps.sh
build="${NAVMAP_BUILD_DIR:-$root/build}"
NAVMAP_BUILD_DIR="$build" scripts/build.sh -DNAVMAP_WITH_WERROR=ON -DNAVMAP_WITH_TESTS=ON -DNAVMAP_WITH_BENCH=ON
cd "$build"
if [ -z "${NAVMAP_TEST_ARGS:-}" ]; then
  echo "test.sh: leaving out the labels soak (runs of hours), cross (the aarch64 cross build," \
       "scripts/cross-build.sh), arm64 (all of it for aarch64, run under qemu), lint (clang-tidy over the tree, about an hour on two cores)" \
       "and slurm (the sharded compile on a private Slurm cluster; installs slurm-wlm and munge);" \
       "run them with NAVMAP_TEST_ARGS=\"-L <label>\""
fi
# shellcheck disable=SC2086
ctest --output-on-failure --timeout 900 -j 2 ${NAVMAP_TEST_ARGS:--LE soak|cross|arm64|lint|slurm}
