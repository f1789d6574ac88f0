"""Module cycles of a Rust crate, from `cargo modules dependencies` (cargo-modules 0.27).

    cargo install cargo-modules --version 0.27.0 --locked
    cargo modules dependencies --package truckmpc-core --lib --no-externs --no-sysroot --no-uses \
        | python scripts/module_cycles.py [--depth 2]

Reads the crate's item graph (DOT) on standard input, maps every item to its module cut to --depth
path segments below the crate (1: top-level modules such as `params`, `dp`), keeps the "uses"
edges between different modules, and prints each set of modules that reach each other (a cycle).
Exits 1 if there is one. cargo-modules' own --acyclic works on items (a type and its method count as
a cycle), which is not the question here.
"""

import argparse
import re
import sys
from collections import defaultdict

NODE = re.compile(r'^\s*"([^"]+)" \[label="([^|"]*)\|')
EDGE = re.compile(r'^\s*"([^"]+)" -> "([^"]+)" \[label="uses"')


def modules_of(dot: str, depth: int) -> dict[str, set[str]]:
    """The module graph: module -> modules its items use, cut to `depth` segments."""
    kinds, edges = {}, []
    for line in dot.splitlines():
        if m := NODE.match(line):
            kinds[m.group(1)] = m.group(2)
        elif m := EDGE.match(line):
            edges.append((m.group(1), m.group(2)))

    def module(path: str) -> str:
        parts = path.split("::")
        while len(parts) > 1 and not kinds.get("::".join(parts), "").endswith(("mod", "crate")):
            parts.pop()
        return "::".join(parts[: 1 + depth])

    graph: dict[str, set[str]] = defaultdict(set)
    for a, b in edges:
        ma, mb = module(a), module(b)
        if ma != mb and not mb.startswith(ma + "::") and not ma.startswith(mb + "::"):
            graph[ma].add(mb)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected sets of more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                out.append(sorted(group))

    sys.setrecursionlimit(10_000)
    for v in list(graph):
        if v not in index:
            visit(v)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--depth", type=int, default=1, help="module path segments below the crate (default 1)")
    args = parser.parse_args()
    graph = modules_of(sys.stdin.read(), args.depth)
    found = cycles(graph)
    for group in found:
        print("cycle:", " <-> ".join(group))
    print(f"{len(graph)} modules, {sum(len(v) for v in graph.values())} module dependencies, {len(found)} cycles")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
