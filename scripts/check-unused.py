#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Shipped code that only tests use: every header of the product's modules must be included by
some other product source (not only by its own .cpp, the tests or the benchmarks). Code that
only tests and benchmarks need lives in tests/support/ or beside the tool that needs it.
Prints each unused header and exits 1 when there is any; run from anywhere (git ls-files).

    scripts/check-unused.py              the tracked sources of this repository
    scripts/check-unused.py --self-test  a generated repository with a used and an unused header
"""
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULES = ("common/", "map/", "render/", "ipc/", "daemon/", "sim/", "cli/", "shaders/")
# Not shipped in a package: development tools built with the tests or the benchmarks.
DEV_TOOLS = ("render/tools/label_quality/",)
# Headers whose users are outside the tree: the installed C API of the client library.
EXTERNAL_API = {"ipc/include/navmap_client.h", "ipc/client/include/navmap_client.h"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def product(path):
    return path.startswith(MODULES) and not path.startswith(DEV_TOOLS) and "/tests/" not in path and "/bench/" not in path


def unused_headers(root):
    files = subprocess.check_output(["git", "-C", root, "ls-files", "*.h", "*.hpp", "*.cpp", "*.c"], text=True).split()
    shipped = [f for f in files if product(f)]
    includes = {}
    for f in shipped:
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
            includes[f] = INCLUDE.findall(fh.read())
    unused = []
    for h in shipped:
        if not h.endswith((".h", ".hpp")) or h in EXTERNAL_API:
            continue
        own = os.path.splitext(os.path.basename(h))[0]
        users = [
            f for f, incs in includes.items()
            if f != h and os.path.splitext(os.path.basename(f))[0] != own
            and any(h == i or h.endswith("/" + i) for i in incs)
        ]
        if not users:
            unused.append(h)
    return unused, sum(1 for f in shipped if f.endswith((".h", ".hpp")))


def self_test():
    tree = {
        "map/include/navmap/map/used.h": "int used();\n",
        "map/src/used.cpp": '#include "navmap/map/used.h"\nint used() { return 1; }\n',
        "map/include/navmap/map/only_tests.h": "int onlyTests();\n",
        "map/src/only_tests.cpp": '#include "navmap/map/only_tests.h"\nint onlyTests() { return 2; }\n',
        "map/src/private_used.h": "int privateUsed();\n",
        "daemon/main.cpp": '#include "navmap/map/used.h"\n#include "private_used.h"\nint main() { return used(); }\n',
        "tests/map/only_tests_test.cpp": '#include "navmap/map/only_tests.h"\n',
    }
    with tempfile.TemporaryDirectory() as d:
        for path, text in tree.items():
            os.makedirs(os.path.dirname(os.path.join(d, path)), exist_ok=True)
            with open(os.path.join(d, path), "w") as fh:
                fh.write(text)
        subprocess.run(["git", "init", "-q", d], check=True)
        subprocess.run(["git", "-C", d, "add", "."], check=True)
        unused, _ = unused_headers(d)
    want = ["map/include/navmap/map/only_tests.h"]
    print(f"check-unused self-test: found {unused}, expected {want}")
    return 0 if unused == want else 1


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    unused, headers = unused_headers(ROOT)
    for h in unused:
        print(f"check-unused: {h}: no product source includes it (only its own source, tests or benchmarks);"
              " move it to tests/support/ or beside the tool that needs it, or delete it")
    if unused:
        print(f"check-unused: {len(unused)} unused header(s)")
        return 1
    print(f"check-unused: each of the product's {headers} headers has a user")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
