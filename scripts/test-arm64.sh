#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The part of the `arm64` label that CI runs beside the native tests (docs/packaging.md "CI"):
# the aarch64 cross build of what the ECU runs and what the checks below need (the programs, the
# client library and its C example, the two test programs of the GPU smoke set), then under
# qemu-user the GPU smoke set against the amd64 goldens (arm64_gpu_smoke), the arm64 navmapd
# serving the amd64 navmap-view (arm64_stream) and the arm64 Debian packages (arm64_packages).
# arm64_unit needs every test program built for aarch64 and stays with developers:
#   NAVMAP_TEST_ARGS="-L arm64" scripts/test.sh
# Runs scripts/test.sh (the native build it needs first: the host navmap-compile makes the store).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
export NAVMAP_CROSS_TARGETS="${NAVMAP_CROSS_TARGETS:-navmapd navmap-ctl navmap-compile navmap-sim navmap-soak \
navmap-view navmap-wayland navmap_client navmap-client-example render_case_tests render_guidance_tests}"
export NAVMAP_TEST_ARGS="${NAVMAP_TEST_ARGS:--L arm64 -E arm64_unit}"
exec "$root/scripts/test.sh"
