#!/usr/bin/env python3
"""Writes the linker script that lays the server's hot code out together (scripts/hot-text.sh).

Reads a callgrind profile of the release server under load (recorded with --demangle=no, so the
names are the symbols' own) and the binary's symbol sizes (`nm -S`), and orders the functions
the load called by the C3 heuristic lld itself applies to a profile's call graph: a function goes
right after the caller that calls it most, while that keeps its cluster dense and under 1 MiB;
clusters are then laid out densest first, so what one request runs shares cache lines and pages.

Each function becomes a section pattern (`-C function-sections`, rustc's default on Linux, puts
each function in `.text.<symbol>`). A Rust symbol's trailing hash (`17h<16 hex>E`) moves with the
crate's build metadata (a dependency's version or features, `--target`), so where the binary has
one function of that path, the hash is a wildcard and the pattern keeps matching through such
changes. Where a generic function has several instances (their paths alike, their hashes not),
the pattern is the exact symbol: a wildcard would pull every cold instance in among the hot ones.
Those go stale when the metadata moves, and match nothing until the script is written again.
Functions called fewer than MIN_CALLS times in the training (start-up, one-off setup) stay out.
Usage: hot-text.py CALLGRIND_OUT NM_OUTPUT OBJECT_SUFFIX [MIN_CALLS, default 100] > hot-text.ld
"""
import collections
import re
import sys

MAX_CLUSTER = 1 << 20  # bytes, as lld's
MAX_DENSITY_DEGRADATION = 8  # as lld's: no merge that makes a cluster 8x less dense


def read_profile(path, suffix):
    """Call counts between functions of the object ending in `suffix`."""
    names, objs = {}, {}

    def define(table, rest):
        m = re.match(r"\((\d+)\)(?: (.*))?$", rest)
        if not m:
            return rest
        if m.group(2) is not None:
            table[m.group(1)] = m.group(2)
        return table.get(m.group(1))

    def plain(name):  # callgrind's recursion level suffix
        return re.sub(r"'\d+$", "", name)

    edges = collections.Counter()
    fn = ob = cfn = cob = None
    for line in open(path, errors="replace"):
        line = line.rstrip("\n")
        if line.startswith("ob="):
            ob = define(objs, line[3:])
        elif line.startswith("fn="):
            fn = define(names, line[3:])
        elif line.startswith("cob="):
            cob = define(objs, line[4:])
        elif line.startswith("cfn="):
            cfn = define(names, line[4:])
        elif line.startswith("calls="):
            callee_ob = cob if cob is not None else ob
            if fn and cfn and ob and ob.endswith(suffix) and callee_ob and callee_ob.endswith(suffix):
                a, b = plain(fn), plain(cfn)
                if a != b:
                    edges[(a, b)] += int(line[6:].split()[0])
            cob = None  # a callee's object is named for its one call
    return edges


def read_sizes(path):
    sizes = {}
    for line in open(path):
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tTwW":
            sizes[parts[3]] = max(sizes.get(parts[3], 0), int(parts[1], 16))
    return sizes


def c3(edges, sizes, min_calls):
    calls = collections.Counter()
    for (_, b), n in edges.items():
        calls[b] += n
    nodes = sorted(n for n in calls if calls[n] >= min_calls and sizes.get(n, 0) > 0)
    index = {n: i for i, n in enumerate(nodes)}
    weight = [calls[n] for n in nodes]  # calls into the function, as lld weighs a section
    best = [(-1, 0)] * len(nodes)  # (caller, calls) of the heaviest caller
    for (a, b), n in edges.items():
        if a in index and b in index:
            i, j = index[a], index[b]
            if n > best[j][1]:
                best[j] = (i, n)
    leader = list(range(len(nodes)))
    members = [[i] for i in range(len(nodes))]
    csize, cweight = [sizes[n] for n in nodes], weight[:]

    def find(i):
        while leader[i] != i:
            leader[i] = leader[leader[i]]
            i = leader[i]
        return i

    def density(c):
        return cweight[c] / max(csize[c], 1)

    # Densest first; ties by name, so the same profile always gives the same script.
    for i in sorted(range(len(nodes)), key=lambda i: (-density(i), nodes[i])):
        pred, heaviest = best[i]
        if pred < 0 or heaviest * 10 <= weight[i]:
            continue
        c, p = find(i), find(pred)
        if c == p or csize[c] + csize[p] > MAX_CLUSTER:
            continue
        merged = (cweight[c] + cweight[p]) / (csize[c] + csize[p])
        if merged * MAX_DENSITY_DEGRADATION < density(p):
            continue
        members[p] += members[c]
        csize[p] += csize[c]
        cweight[p] += cweight[c]
        members[c] = []
        leader[c] = p
    clusters = [c for c in range(len(nodes)) if find(c) == c]
    clusters.sort(key=lambda c: (-density(c), nodes[c]))
    return [nodes[m] for c in clusters for m in members[c]]


HASH = re.compile(r"17h[0-9a-f]{16}E")


def pattern(symbol, instances):
    """The section pattern for a symbol; None when the symbol cannot be a pattern safely."""
    if any(ch in symbol for ch in "[]?*(){}; \"'"):
        return None
    wild = HASH.sub("17h*E", symbol)
    return wild if instances[wild] == 1 else symbol


def main():
    profile, nm, suffix = sys.argv[1:4]
    min_calls = int(sys.argv[4]) if len(sys.argv) > 4 else 100
    edges = read_profile(profile, suffix)
    sizes = read_sizes(nm)
    order = c3(edges, sizes, min_calls)
    instances = collections.Counter(HASH.sub("17h*E", s) for s in sizes)
    seen, lines = set(), []
    for symbol in order:
        p = pattern(symbol, instances)
        if p and p not in seen:
            seen.add(p)
            lines.append(f"    *(.text.{p})")
    if not lines:
        sys.exit("hot-text: the profile ran no function of the binary")
    print("/* Generated by scripts/hot-text.sh: the functions a request runs, laid out together")
    print("   (ARCHITECTURE.md, \"The hot path's code layout\"). Do not edit by hand. */")
    print("SECTIONS\n{\n  .text.hot : {")
    print("\n".join(lines))
    print("  }\n}\nINSERT BEFORE .text;")
    print(f"hot-text: {len(lines)} functions", file=sys.stderr)


if __name__ == "__main__":
    main()
