#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Size limits of the product's C++ (CONTRIBUTING.md "Size"): no function over 150 lines and no
file over 700 lines outside tests/ and bench/. A function's length runs from the line of its
opening brace to the line of its closing brace (comments and string literals are blanked
first, so braces in them do not count; a lambda counts within the function that holds it).
Prints every breach and exits 1 when there is any.

    scripts/check-sizes.py            the tracked sources
    scripts/check-sizes.py FILE...    the given files (any path)
    scripts/check-sizes.py --self-test  generated files at, over and under the limits
"""
import os
import re
import subprocess
import sys
import tempfile

MAX_FUNCTION_LINES = 150
MAX_FILE_LINES = 700
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCES = (".h", ".hpp", ".cpp", ".cc", ".c")
RAW_STRING = re.compile(r'R"([^(\s]{0,16})\(')


def blank(src):
    """Comments, string and character literals replaced by blanks; line breaks kept."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            i = n if j < 0 else j
            continue
        if src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * src.count("\n", i, j))
            i = j
            continue
        m = RAW_STRING.match(src, i)
        if m and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            end = ")" + m.group(1) + '"'
            j = src.find(end, m.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + "\n" * src.count("\n", i, j))
            i = j
            continue
        c = src[i]
        if c in "\"'" and not (c == "'" and i > 0 and src[i - 1].isalnum()):  # 1'000 digit separators
            j = i + 1
            while j < n and src[j] != c and src[j] != "\n":
                j += 2 if src[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def functions(text):
    """(first line, lines, head) of each function body at namespace or class scope."""
    src = blank(text)
    stack, found, line, last = [], [], 1, 0
    for i, c in enumerate(src):
        if c == "\n":
            line += 1
        elif c == "{":
            head = " ".join(src[last:i].split())
            outer_ok = all(kind in ("namespace", "class") for kind, _, _ in stack)
            if re.search(r'\bnamespace\b|\bextern\s*""', head):
                kind = "namespace"
            elif re.search(r"\b(class|struct|union|enum)\b[^()]*$", head):
                kind = "class"
            elif outer_ok and ")" in head and not head.endswith("="):
                kind = "function"
            else:
                kind = "block"
            stack.append((kind, line, head))
            last = i + 1
        elif c == "}":
            if stack:
                kind, first, head = stack.pop()
                if kind == "function":
                    found.append((first, line - first + 1, head[-90:]))
            last = i + 1
        elif c == ";":
            last = i + 1
    return found


def tracked():
    files = subprocess.check_output(["git", "-C", ROOT, "ls-files"], text=True).split()
    return [os.path.join(ROOT, f) for f in files
            if f.endswith(SOURCES) and not f.startswith(("tests/", "bench/", "build"))
            and "/tests/" not in f and "/bench/" not in f]


def check(paths):
    breaches = []
    largest_file, largest_function = (0, ""), (0, "")
    for path in paths:
        with open(path, encoding="utf-8", errors="replace") as fh:
            text = fh.read()
        name = os.path.relpath(path, ROOT) if path.startswith(ROOT) else path
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        largest_file = max(largest_file, (lines, name))
        if lines > MAX_FILE_LINES:
            breaches.append(f"{name}: {lines} lines (limit {MAX_FILE_LINES})")
        for first, length, head in functions(text):
            largest_function = max(largest_function, (length, f"{name}:{first} {head}"))
            if length > MAX_FUNCTION_LINES:
                breaches.append(f"{name}:{first}: function of {length} lines (limit {MAX_FUNCTION_LINES}): {head}")
    return breaches, largest_file, largest_function


def self_test():
    def body(n):  # a function whose braces span n lines
        return "int f(int a) {\n" + "    a += 1;\n" * (n - 2) + "}\n"
    cases = {
        "at_limit.cpp": (body(MAX_FUNCTION_LINES), 0),
        "over_limit.cpp": (body(MAX_FUNCTION_LINES + 1), 1),
        "method_over.cpp": ("namespace n {\nclass C {\n" + body(MAX_FUNCTION_LINES + 5) + "};\n}\n", 1),
        "braces_in_text.cpp": ('const char* s = "{{{";\n// }\n' + body(10) + "/* { */\n", 0),
        "raw_string.cpp": ('const char* r = R"x({ ) })x";\n' + body(MAX_FUNCTION_LINES + 1), 1),
        "long_file.h": ("int x;\n" * (MAX_FILE_LINES + 1), 1),
        "lambda_inside.cpp": ("void g() {\n auto l = [] {\n" + "  ;\n" * (MAX_FUNCTION_LINES) + " };\n}\n", 1),
    }
    failed = 0
    with tempfile.TemporaryDirectory() as d:
        for name, (text, want) in cases.items():
            path = os.path.join(d, name)
            with open(path, "w") as fh:
                fh.write(text)
            got = len(check([path])[0])
            if got != want:
                print(f"check-sizes self-test: {name}: {got} breach(es), expected {want}")
                failed += 1
    print(f"check-sizes self-test: {len(cases) - failed} of {len(cases)} cases right")
    return 1 if failed else 0


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    breaches, largest_file, largest_function = check([os.path.abspath(a) for a in argv] if argv else tracked())
    for b in breaches:
        print(f"check-sizes: {b}")
    print(f"check-sizes: largest file {largest_file[1]} ({largest_file[0]} lines); largest function "
          f"{largest_function[1]} ({largest_function[0]} lines)")
    if breaches:
        print(f"check-sizes: {len(breaches)} breach(es) of the size limits")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
