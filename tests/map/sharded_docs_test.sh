#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# docs/sharded-compile.md quotes the Slurm job scripts (scripts/slurm/*.sbatch) exactly, each in a
# ```bash block of its own, so that what the page shows is what compile-slurm.sh submits.
#   sharded_docs_test.sh <source dir>
set -euo pipefail
src="$1"
python3 - "$src/docs/sharded-compile.md" "$src"/scripts/slurm/*.sbatch <<'EOF_PY'
import re, sys
doc = open(sys.argv[1]).read()
blocks = re.findall(r"^```bash\n(.*?)^```$", doc, re.S | re.M)
scripts = sys.argv[2:]
if len(scripts) < 2:
    sys.exit(f"FAIL: expected the shard and merge job scripts, found {scripts}")
failed = False
for path in scripts:
    text = open(path).read()
    if text not in blocks:
        print(f"FAIL: {sys.argv[1]} has no ```bash block equal to {path}")
        failed = True
if failed:
    sys.exit(1)
print(f"{len(scripts)} job scripts quoted exactly in {sys.argv[1]}")
EOF_PY
