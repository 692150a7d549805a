#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A sharded compile on a Slurm cluster (docs/sharded-compile.md "Slurm"): the N shards as one job
# array (scripts/slurm/shard.sbatch), the merge as a job that depends on it with afterok
# (scripts/slurm/merge.sbatch), then waits for the merge and reports.
#   scripts/compile-slurm.sh N OUT --osm region.osm.pbf --dem N42E001.hgt [other navmap-compile options]
# Talks to the cluster that sbatch finds (SLURM_CONF); scripts/slurm-local.sh starts a private one.
# OUT, its folder OUT.shards/ (the shard stores and the jobs' logs) and the input must be on
# storage that every node sees, under the same paths; relative paths are taken from the current
# folder, where the jobs start too. OUT.shards/ is removed after a successful merge unless
# NAVMAP_KEEP_SHARDS=1. A failed shard cancels the merge: the failed tasks' logs are printed
# and the exit status is 1; so it is when the merge fails or does not end within the timeout.
#   NAVMAP_COMPILE       navmap-compile for the jobs (default build/map/navmap-compile, else PATH);
#                        sbatch hands it to the jobs in their environment
#   NAVMAP_JOBS          shards running at a time (the array's %limit; default: as the cluster allows)
#   NAVMAP_SLURM_ARGS    more sbatch options for both jobs, e.g. "--partition=batch --account=maps --mem=2G"
#   NAVMAP_SLURM_TIMEOUT seconds to wait for the merge to end (default 86400); then both jobs are cancelled
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
me="compile-slurm"
# shellcheck source=scripts/shard-args.sh
. "$root/scripts/shard-args.sh"
shard_args "$0" "$@"
shift 2
for tool in sbatch scontrol scancel; do
  command -v "$tool" >/dev/null 2>&1 || { echo "$me: $tool not found (Slurm's client commands, Debian package slurm-client)" >&2; exit 2; }
done
if [[ "$compile" == */* ]]; then compile="$(cd "$(dirname "$compile")" && pwd)/$(basename "$compile")"; fi
export NAVMAP_COMPILE="$compile"
timeout_s="${NAVMAP_SLURM_TIMEOUT:-86400}"
read -r -a extra <<<"${NAVMAP_SLURM_ARGS:-}"

mkdir -p "$(dirname "$out")"
out="$(cd "$(dirname "$out")" && pwd)/$(basename "$out")"
parts="$out.shards"
rm -rf "$parts"
mkdir -p "$parts"
rm -f "$out"

start=$SECONDS
array="0-$((n - 1))${NAVMAP_JOBS:+%$NAVMAP_JOBS}"
jid="$(sbatch --parsable --array="$array" --output="$parts/part-%a.log" "${extra[@]}" \
  "$root/scripts/slurm/shard.sbatch" "$n" "$parts" "$@")"
jid="${jid%%;*}"
mid=""
cancel() { scancel "$jid" ${mid:+"$mid"} 2>/dev/null || true; }
trap 'cancel; exit 130' INT
trap 'cancel; exit 143' TERM
mid="$(sbatch --parsable --dependency="afterok:$jid" --kill-on-invalid-dep=yes --output="$parts/merge.log" \
  "${extra[@]}" "$root/scripts/slurm/merge.sbatch" "$n" "$parts" "$out")"
mid="${mid%%;*}"
echo "$me: $n shards as job array $jid ($array), the merge as job $mid (afterok:$jid)"

# The state of a job, or of each task of an array: lines "TASK STATE EXIT" (TASK - for a plain
# job), from scontrol while the controller remembers the job, else from the accounting (sacct).
states() {
  local lines
  if lines="$(scontrol show job -o "$1" 2>/dev/null)" && [ -n "$lines" ]; then
    awk '{ t = "-"; s = "?"; e = "?";
           for (i = 1; i <= NF; i++) {
             if ($i ~ /^ArrayTaskId=/) t = substr($i, 13);
             if ($i ~ /^JobState=/) s = substr($i, 10);
             if ($i ~ /^ExitCode=/) e = substr($i, 10) } print t, s, e }' <<<"$lines"
  elif command -v sacct >/dev/null 2>&1; then
    sacct -n -X -P -j "$1" -o JobID,State,ExitCode 2>/dev/null \
      | awk -F'|' '{ t = "-"; if (split($1, p, "_") == 2) t = p[2]; split($2, s, " "); print t, s[1], $3 }'
  fi
}
merge_state=""
while :; do
  merge_state="$(states "$mid" | awk '{ print $2; exit }')"
  case "$merge_state" in
    COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | PREEMPTED | BOOT_FAIL | DEADLINE) break ;;
  esac
  if [ $((SECONDS - start)) -ge "$timeout_s" ]; then
    cancel
    echo "$me: the merge (job $mid) had not ended after $timeout_s s (NAVMAP_SLURM_TIMEOUT); both jobs cancelled." >&2
    echo "$me: the shards: $(states "$jid" | sort -n | awk '{ printf "%s%s %s", (NR > 1 ? ", " : ""), $1, $2 }')" >&2
    exit 1
  fi
  sleep 2
done

if [ "$merge_state" != COMPLETED ]; then
  failed="$(states "$jid" | awk '$2 != "COMPLETED" { print $1 " " $2 " " $3 }' | sort -n)"
  if [ -n "$failed" ]; then
    echo "$me: shard task(s) did not succeed, so the merge was cancelled and nothing is merged (logs: $parts/):" >&2
    while read -r task state code; do
      echo "shard $task/$n: $state (exit $code):" >&2
      [ -f "$parts/part-$task.log" ] && tail -n 5 "$parts/part-$task.log" >&2
    done <<<"$failed"
  else
    echo "$me: the merge (job $mid) ended $merge_state:" >&2
    [ -f "$parts/merge.log" ] && tail -n 5 "$parts/merge.log" >&2
  fi
  exit 1
fi
cat "$parts/merge.log" 2>/dev/null || true
[ "${NAVMAP_KEEP_SHARDS:-0}" = 1 ] || rm -rf "$parts"
echo "$me: $out in $((SECONDS - start)) s"
