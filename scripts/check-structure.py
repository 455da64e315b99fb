#!/usr/bin/python3
"""Checks the size limits of the C++ sources: no file in source/ over 600
lines, no function over 80 lines (from its signature to its closing brace).

    scripts/check-structure.py [ROOT]        exit 1 and one line per violation
    scripts/check-structure.py --self-test   shows that both limits can fail

Functions are found by the project's layout (clang-format, Allman braces): a
brace alone on a line at namespace depth (indent 0, 2 or 4) that follows a
line ending in ')' (optionally 'const', 'override', 'noexcept'), up to the
brace at the same indent. Lambdas and nested blocks count as part of their
function.
"""
import os
import re
import sys
import tempfile

MAX_FILE_LINES = 600
MAX_FUNCTION_LINES = 80
SIGNATURE_END = re.compile(r"\)\s*(const)?\s*(override)?\s*(noexcept)?\s*$")


def functions(lines):
    """(first line, number of lines, signature) of each function."""
    found = []
    i = 0
    while i < len(lines):
        m = re.match(r"^( {0}| {2}| {4})\{$", lines[i])
        if m and i > 0 and SIGNATURE_END.search(lines[i - 1]):
            indent = m.group(1)
            start = i - 1
            while start > 0 and not re.match("^" + indent + r"[A-Za-z~_]", lines[start]):
                start -= 1
            end = i + 1
            while end < len(lines) and lines[end] != indent + "}":
                end += 1
            found.append((start + 1, end - start + 1, lines[start].strip()))
            i = end
        i += 1
    return found


def check(root):
    problems = []
    for folder, _, files in os.walk(os.path.join(root, "source")):
        for name in sorted(files):
            if not name.endswith((".cc", ".h")):
                continue
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, root)
            with open(path) as f:
                lines = f.read().split("\n")
            if len(lines) - 1 > MAX_FILE_LINES:
                problems.append(f"{rel}: {len(lines) - 1} lines (at most {MAX_FILE_LINES})")
            for first, n, signature in functions(lines):
                if n > MAX_FUNCTION_LINES:
                    problems.append(f"{rel}:{first}: {signature[:60]}: {n} lines (at most {MAX_FUNCTION_LINES})")
    return problems


def self_test():
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "source"))
        body = "\n".join(["    x += 1;"] * 79)
        with open(os.path.join(root, "source", "long.cc"), "w") as f:
            f.write("namespace a\n{\n  void f(int &x)\n  {\n" + body + "\n  }\n}\n")
        with open(os.path.join(root, "source", "short.cc"), "w") as f:
            f.write("void g()\n{\n}\n" + "\n" * 600)
        problems = check(root)
    ok = any("long.cc:3" in p for p in problems) and any("short.cc: 603 lines" in p for p in problems)
    print("self-test:", "the checker finds a long function and a long file" if ok else "FAILED", problems)
    return 0 if ok else 1


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--self-test":
        return self_test()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    problems = check(root)
    for p in problems:
        print(p)
    print(f"{len(problems)} violations")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
