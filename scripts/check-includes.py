#!/usr/bin/env python3
"""The module include graph of wirefem and its rules.

A module is a folder of include/wirefem and source (core, contact, discrete,
fem, ...); main.cc is the module 'main'. An arrow A -> B means a file of A
includes <wirefem/B/...>. The rules:
  1. core includes no other module (it is below both models);
  2. only simulation and main include a model (discrete, fem);
  3. the module graph has no cycle.

Usage: check-includes.py [ROOT]       prints the graph; exit 1 on a violation
       check-includes.py --self-test  checks that each rule catches a break
"""
import os
import re
import sys
import tempfile

MODELS = {"discrete", "fem"}
MAY_INCLUDE_MODELS = {"simulation", "main"}
INCLUDE = re.compile(r'^\s*#\s*include\s*<wirefem/([^/>]+)/[^>]+>', re.M)


def module_graph(root):
    edges = {}
    for top in ("include/wirefem", "source"):
        base = os.path.join(root, top)
        for folder, _, files in os.walk(base):
            for name in files:
                if not name.endswith((".h", ".cc")):
                    continue
                rel = os.path.relpath(os.path.join(folder, name), base)
                module = rel.split(os.sep)[0] if os.sep in rel else "main"
                with open(os.path.join(folder, name), encoding="utf-8") as f:
                    for target in INCLUDE.findall(f.read()):
                        if target != module:
                            edges.setdefault(module, {}).setdefault(target, os.path.join(top, rel))
    return edges


def find_cycle(edges):
    state, stack = {}, []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(edges.get(node, {})):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(edges):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def violations(edges):
    found = []
    for target, where in sorted(edges.get("core", {}).items()):
        found.append(f"core includes {target} ({where})")
    for module, targets in sorted(edges.items()):
        for target, where in sorted(targets.items()):
            if target in MODELS and module not in MAY_INCLUDE_MODELS:
                found.append(f"{module} includes the model {target} ({where})")
    cycle = find_cycle(edges)
    if cycle:
        found.append("cycle: " + " -> ".join(cycle))
    return found


def self_test():
    cases = {
        "clean": ({"core/a.h": "", "fem/b.h": "#include <wirefem/core/a.h>",
                   "simulation/c.cc": "#include <wirefem/fem/b.h>"}, 0),
        "core up": ({"core/a.h": "#include <wirefem/scene/p.h>", "scene/p.h": ""}, 1),
        "model from below": ({"analysis/a.cc": "#include <wirefem/fem/b.h>", "fem/b.h": ""}, 1),
        "cycle": ({"io/a.h": "#include <wirefem/scene/p.h>", "scene/p.h": "#include <wirefem/io/a.h>"}, 1),
    }
    ok = True
    for name, (files, expected) in cases.items():
        with tempfile.TemporaryDirectory() as root:
            for path, text in files.items():
                full = os.path.join(root, "include/wirefem", path)
                os.makedirs(os.path.dirname(full), exist_ok=True)
                with open(full, "w", encoding="utf-8") as f:
                    f.write(text + "\n")
            got = len(violations(module_graph(root)))
            if (got > 0) != (expected > 0):
                print(f"FAIL: self test '{name}': {got} violations, expected {expected}")
                ok = False
    print("self test passed" if ok else "self test failed")
    return 0 if ok else 1


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    edges = module_graph(root)
    for module in sorted(edges):
        print(f"{module} -> {', '.join(sorted(edges[module]))}")
    found = violations(edges)
    for v in found:
        print("violation:", v)
    print(f"{len(found)} violations")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
