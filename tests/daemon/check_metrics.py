#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# Parses a /metrics scrape with the Prometheus client library's own text parser (Debian:
# python3-prometheus-client) and fails on what Prometheus would reject or misread: a family
# declared twice, a sample (name and labels) twice, a family without HELP or TYPE, or a name in
# milliseconds (Prometheus wants base units: seconds, bytes).
# Usage: check_metrics.py FILE   Prints "families N samples M" and exits 0, else the problems, 1.
# Exit 77 when the parser is not installed.
import collections
import re
import sys

try:
    from prometheus_client.parser import text_string_to_metric_families
except ImportError:
    print("python3-prometheus-client is not installed (apt-get install python3-prometheus-client)")
    sys.exit(77)

text = open(sys.argv[1], encoding="utf-8").read()
problems = []
# Blocks as written: the parser merges nothing, so count HELP and TYPE lines per name as well.
for kind in ("HELP", "TYPE"):
    counts = collections.Counter(re.findall(r"^# %s (\S+)" % kind, text, re.M))
    problems += ["family %s has %d %s lines" % (n, c, kind) for n, c in counts.items() if c > 1]
try:
    families = list(text_string_to_metric_families(text))
except Exception as e:  # the parser's own verdict on malformed text
    print("not parseable: %s" % e)
    sys.exit(1)
names = collections.Counter(f.name for f in families)
problems += ["family %s appears %d times" % (n, c) for n, c in names.items() if c > 1]
seen = collections.Counter()
for f in families:
    if not f.documentation:
        problems.append("family %s has no HELP" % f.name)
    if f.type in ("unknown", "untyped"):
        problems.append("family %s has no TYPE" % f.name)
    if re.search(r"_(ms|milliseconds|kb|mb|mib)(_total)?$", f.name):
        problems.append("family %s is not in base units" % f.name)
    for s in f.samples:
        seen[(s.name, tuple(sorted(s.labels.items())))] += 1
problems += ["sample %s%s appears %d times" % (n, dict(l), c) for (n, l), c in seen.items() if c > 1]
if problems:
    print("\n".join(problems))
    sys.exit(1)
print("families %d samples %d" % (len(families), sum(len(f.samples) for f in families)))
for f in families:
    print("%s %s %d" % (f.name, f.type, len(f.samples)))
