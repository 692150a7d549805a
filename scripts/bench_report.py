#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Merges and compares the JSON of scripts/bench.sh (docs/benchmarks/README.md).

  bench_report.py merge --commit C --out F [--load L] PROGRAM.json ...
      one JSON: machine, commit, date, load average per program, every program's figures
  bench_report.py compare --a REV --b REV --rounds N --out F --dir D
      D holds A-<round>-<program>.json and B-<round>-<program>.json; prints B/A per figure,
      its spread over the rounds, and flags figures worse by more than the spread (exit 3)

A figure is a benchmark's real_time or one of its counters, named "<program>:<benchmark>:<key>".
Which way is worse follows the name: times, memory and work counters grow worse; fps and
rates shrink worse; other figures are listed but never flagged.
"""
import argparse
import datetime
import glob
import json
import math
import os
import platform
import re
import statistics
import sys

STANDARD = {"name", "run_name", "run_type", "repetitions", "repetition_index", "threads", "iterations",
            "cpu_time", "time_unit", "family_index", "per_family_instance_index", "aggregate_name",
            "aggregate_unit", "label", "error_occurred", "error_message"}
HIGHER_WORSE = re.compile(r"(real_time|_ms$|_us$|_s$|seconds|rss|_mb$|_mib$|bytes|_tests$|_cells$|latency|"
                          r"p50|p95|p99|draw_calls|triangles|segments)")
LOWER_WORSE = re.compile(r"(fps|per_s$|throughput|rate$)")
MIN_SPREAD = 0.02  # figures within 2 % are never flagged, however steady the rounds


def direction(key):
    if LOWER_WORSE.search(key):
        return "lower_worse"
    if HIGHER_WORSE.search(key):
        return "higher_worse"
    return "info"


def flatten(prefix, value, out):
    if isinstance(value, bool):
        return
    if isinstance(value, (int, float)):
        if math.isfinite(value):
            out[prefix] = float(value)
    elif isinstance(value, dict):
        for k, v in value.items():
            flatten(f"{prefix}.{k}" if prefix else str(k), v, out)


def figures(program, doc):
    """Figures of one program's JSON: Google Benchmark entries, or any JSON's numeric leaves."""
    out = {}
    if not isinstance(doc, dict):
        return out
    if isinstance(doc.get("benchmarks"), list):
        for b in doc["benchmarks"]:
            if not isinstance(b, dict) or b.get("error_occurred"):
                continue
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            name = b.get("name", "?")
            for k, v in b.items():
                if k in STANDARD or isinstance(v, bool) or not isinstance(v, (int, float)):
                    continue
                if math.isfinite(v):
                    key = "real_time_" + b.get("time_unit", "ns") if k == "real_time" else k
                    out[f"{program}:{name}:{key}"] = float(v)
    elif "error" not in doc:
        flat = {}
        flatten("", doc, flat)
        out.update({f"{program}::{k}": v for k, v in flat.items()})
    return out


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        return {"error": f"{os.path.basename(path)}: {e}"}


def machine(context):
    m = {"host": platform.node(), "system": platform.platform(), "cpus": os.cpu_count()}
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            model = [l.split(":", 1)[1].strip() for l in f if l.startswith("model name")]
        if model:
            m["cpu"] = model[0]
    except OSError:
        pass
    for k in ("num_cpus", "mhz_per_cpu", "library_build_type"):
        if k in context:
            m[k] = context[k]
    return m


def merge(args):
    programs = {}
    context = {}
    for path in args.files:
        name = os.path.basename(path)[:-len(".json")]
        doc = load(path)
        if isinstance(doc, dict) and isinstance(doc.get("context"), dict) and not context:
            context = doc["context"]
        programs[name] = {"figures": figures(name, doc)}
        if isinstance(doc, dict) and "error" in doc:
            programs[name]["error"] = doc["error"]
    loads = {}
    if args.load and os.path.exists(args.load):
        with open(args.load, encoding="utf-8") as f:
            for line in f:
                p = line.split()
                if len(p) == 7:
                    loads[p[0]] = {"before": [float(x) for x in p[1:4]], "after": [float(x) for x in p[4:7]]}
    for name, load_avg in loads.items():
        programs.setdefault(name, {})["load_average"] = load_avg
    report = {"commit": args.commit, "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
              "machine": machine(context), "programs": programs}
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(report, f, indent=1, sort_keys=True)
    errors = [n for n, p in programs.items() if "error" in p]
    print(f"bench_report: {sum(len(p.get('figures', {})) for p in programs.values())} figures from "
          f"{len(programs)} programs" + (f"; failed: {', '.join(errors)}" if errors else ""))
    return 1 if errors else 0


def compare_figures(rounds_a, rounds_b):
    """rounds_a/b: one {figure: value} per round. Returns rows for figures present in all rounds."""
    rows = []
    keys = set.intersection(*(set(r) for r in rounds_a + rounds_b)) if rounds_a and rounds_b else set()
    for key in sorted(keys):
        a = [r[key] for r in rounds_a]
        b = [r[key] for r in rounds_b]
        if any(x == 0 for x in a):
            continue
        ratios = [y / x for x, y in zip(a, b)]
        ratio = statistics.median(ratios)
        med_a, med_b = statistics.median(a), statistics.median(b)
        spread = max((max(ratios) - min(ratios)) / 2,
                     (max(a) - min(a)) / (2 * abs(med_a)) if med_a else 0.0,
                     (max(b) - min(b)) / (2 * abs(med_b)) if med_b else 0.0, MIN_SPREAD)
        d = direction(key.rsplit(":", 1)[-1])
        worse = (d == "higher_worse" and ratio > 1 + spread) or (d == "lower_worse" and ratio < 1 - spread)
        better = (d == "higher_worse" and ratio < 1 - spread) or (d == "lower_worse" and ratio > 1 + spread)
        rows.append({"figure": key, "a": med_a, "b": med_b, "ratio": ratio, "spread": spread, "direction": d,
                     "verdict": "worse" if worse else "better" if better else "same"})
    return rows


def compare(args):
    rounds_a, rounds_b = [], []
    for r in range(1, args.rounds + 1):
        fa, fb = {}, {}
        for path in glob.glob(os.path.join(args.dir, f"A-{r}-*.json")):
            name = os.path.basename(path)[len(f"A-{r}-"):-len(".json")]
            fa.update(figures(name, load(path)))
        for path in glob.glob(os.path.join(args.dir, f"B-{r}-*.json")):
            name = os.path.basename(path)[len(f"B-{r}-"):-len(".json")]
            fb.update(figures(name, load(path)))
        rounds_a.append(fa)
        rounds_b.append(fb)
    rows = compare_figures(rounds_a, rounds_b)
    report = {"a": args.a, "b": args.b, "rounds": args.rounds,
              "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
              "machine": machine({}), "figures": rows}
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(report, f, indent=1)
    print(f"B = {args.b} against A = {args.a}, {args.rounds} interleaved rounds; ratio B/A (median), +- spread")
    print(f"{'figure':<78} {'A':>12} {'B':>12} {'B/A':>7} {'+-':>6}  verdict")
    for row in rows:
        if row["direction"] == "info":
            continue
        print(f"{row['figure'][:78]:<78} {row['a']:>12.4g} {row['b']:>12.4g} {row['ratio']:>7.3f} "
              f"{row['spread']:>6.3f}  {row['verdict']}")
    worse = [r["figure"] for r in rows if r["verdict"] == "worse"]
    if not rows:
        print("bench_report: no figure is present in every round of both builds")
        return 1
    print(f"{len(rows)} figures, {sum(r['verdict'] == 'better' for r in rows)} better, {len(worse)} worse"
          + (": " + ", ".join(worse) if worse else ""))
    return 3 if worse else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("merge")
    m.add_argument("--commit", required=True)
    m.add_argument("--out", required=True)
    m.add_argument("--load")
    m.add_argument("files", nargs="+")
    c = sub.add_parser("compare")
    c.add_argument("--a", required=True)
    c.add_argument("--b", required=True)
    c.add_argument("--rounds", type=int, required=True)
    c.add_argument("--out", required=True)
    c.add_argument("--dir", required=True)
    args = ap.parse_args()
    return merge(args) if args.cmd == "merge" else compare(args)


if __name__ == "__main__":
    sys.exit(main())
