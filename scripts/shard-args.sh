# shellcheck shell=bash
# SPDX-License-Identifier: Apache-2.0
# Sourced by compile-sharded.sh and compile-slurm.sh: their shared arguments.
#   shard_args "$0" "$@"; shift 2   checks "N OUT --osm FILE ..." and sets n, out and
#                          compile: $NAVMAP_COMPILE, else build/map/navmap-compile, else the one on PATH.
# Exits 2 with a usage line or the reason on a wrong N or a missing navmap-compile.
# shellcheck disable=SC2034  # n, out and compile are the caller's
shard_args() {
  local me="$1" root
  shift
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  if [ $# -lt 3 ]; then
    echo "usage: $me N OUT --osm FILE [--dem FILE ...] [navmap-compile options]" >&2
    exit 2
  fi
  n="$1"
  out="$2"
  if ! [[ "$n" =~ ^[0-9]+$ ]] || [ "$n" -lt 1 ] || [ "$n" -gt 4096 ]; then
    echo "$me: N must be a number of shards in [1, 4096], not '$n'" >&2
    exit 2
  fi
  compile="${NAVMAP_COMPILE:-}"
  if [ -z "$compile" ]; then
    if [ -x "$root/build/map/navmap-compile" ]; then compile="$root/build/map/navmap-compile"; else compile="navmap-compile"; fi
  fi
  command -v "$compile" >/dev/null 2>&1 || {
    echo "$me: $compile not found (build first, or set NAVMAP_COMPILE)" >&2
    exit 2
  }
}
