#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The SPDX license line of every source file (the code is Apache-2.0, LICENSE; the data in data/
# keeps its own licences, data/ATTRIBUTION.md):
#   scripts/license-headers.sh --check   lists the files without it, exits 1 when there are any
#   scripts/license-headers.sh --add     adds it as the first line (after a #! line), idempotent
# Files: C/C++ sources and headers (.c .cpp .h .h.in), GLSL (.glsl .vert .frag), shell and Python
# scripts (.sh .py), Slurm job scripts (.sbatch), CMake files (CMakeLists.txt, .cmake, .cmake.in). Run --add after merging a
# branch that brings new files.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mode="${1:---check}"
line_for() {
    case "$1" in
        *.c|*.cpp|*.h|*.h.in|*.glsl|*.vert|*.frag) echo "// SPDX-License-Identifier: Apache-2.0" ;;
        *) echo "# SPDX-License-Identifier: Apache-2.0" ;;
    esac
}
list() {
    cd "$root"
    if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
        git ls-files --cached --others --exclude-standard
    else
        find . -path ./build -prune -o -type f -print | sed 's|^\./||'
    fi | grep -E '(\.(c|cpp|h|glsl|vert|frag|sh|py|sbatch|cmake)|\.h\.in|\.cmake\.in|(^|/)CMakeLists\.txt)$' \
       | grep -v -E '^(build[^/]*|out)/' | sort
}
missing=0
while IFS= read -r f; do
    if head -n 3 "$root/$f" | grep -q 'SPDX-License-Identifier: Apache-2.0'; then continue; fi
    if [ "$mode" = --add ]; then
        line="$(line_for "$f")"
        tmp="$(mktemp)"
        if head -n 1 "$root/$f" | grep -q '^#!'; then
            { head -n 1 "$root/$f"; echo "$line"; tail -n +2 "$root/$f"; } > "$tmp"
        else
            { echo "$line"; cat "$root/$f"; } > "$tmp"
        fi
        cat "$tmp" > "$root/$f"  # keeps the file's mode
        rm -f "$tmp"
        echo "added: $f"
    else
        echo "no SPDX-License-Identifier: $f"
        missing=$((missing + 1))
    fi
done < <(list)
if [ "$mode" = --check ]; then
    echo "license-headers: $(list | wc -l) files checked, $missing without the SPDX line"
    [ "$missing" -eq 0 ]
fi
