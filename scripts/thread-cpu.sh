#!/usr/bin/env bash
# Where a server's CPU goes under load, by thread: the binary serves the paper's "Get the vase."
# (REST, structured or as text) under wrk at concurrency 64 for SECONDS, and for each of its
# threads this prints the CPU time it spent (the scheduler's own count, /proc/PID/task/TID/
# schedstat, in ns, not the 10 ms ticks of /stat) and its voluntary and involuntary context
# switches over the run. Threads are grouped by name (rayon's pool threads carry the binary's
# name, as the main thread does; the main thread is the one whose id is the process id). For
# what a thread that is not on the request path (rayon's, the store's) costs the request that is.
# A thread that exits during the run (the blocking pool's, after 1 s idle) is not counted.
# Traffic stays on 127.0.0.1; installs wrk when missing.
# Usage: scripts/thread-cpu.sh BINARY [SECONDS, default 10] [structured|text]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
binary=$1 seconds=${2:-10} body=${3:-structured}
need_tools wrk
work=$(mktemp -d)
"$binary" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/threads.db" >"$work/out" 2>"$work/err" &
pid=$!
trap 'kill $pid 2>/dev/null || true; rm -rf "$work"' EXIT
addr=$(listening_addr "$work/out") || { cat "$work/err" >&2; exit 1; }
paper_wrk "$work" "$body" "$addr"
snapshot() { # -> lines "tid name cpu_ns voluntary involuntary"
  local t
  for t in /proc/"$pid"/task/*; do
    echo "${t##*/} $(tr ' ' _ <"$t/comm") $(cut -d' ' -f1 "$t/schedstat") $(awk '/^voluntary_ctxt/ {v = $2} /^nonvoluntary_ctxt/ {n = $2} END {print v, n}' "$t/status")"
  done
}
snapshot >"$work/before"
rps=$(wrk -t2 -c64 -d"${seconds}s" -s "$work/body.lua" "http://$addr/v1/clarify" | awk '/Requests\/sec/ {print $2}')
snapshot >"$work/after"
python3 - "$work" "$pid" "$rps" "$seconds" <<'PY'
import collections, sys
work, pid, rps, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
def read(name):
    rows = {}
    for line in open(f"{work}/{name}"):
        tid, comm, ns, vol, invol = line.split()
        rows[tid] = (comm, int(ns), int(vol), int(invol))
    return rows
before, after = read("before"), read("after")
groups = collections.defaultdict(lambda: [0, 0, 0, 0])
for tid, (comm, ns, vol, invol) in after.items():
    b = before.get(tid, (comm, 0, 0, 0))  # a thread started during the run counts from zero
    name = "main" if tid == pid else comm
    g = groups[name]
    g[0] += 1; g[1] += ns - b[1]; g[2] += vol - b[2]; g[3] += invol - b[3]
requests = rps * seconds
total = sum(g[1] for g in groups.values())
print(f"{requests:.0f} requests ({rps:.0f}/s); server CPU {total / 1e6:.0f} ms, {total / 1e3 / requests:.1f} µs a request")
print("| threads | name | CPU ms | share | voluntary switches | involuntary |")
print("|---|---|---|---|---|---|")
for name, (n, ns, vol, invol) in sorted(groups.items(), key=lambda kv: -kv[1][1]):
    print(f"| {n} | {name} | {ns / 1e6:.1f} | {ns / total:.2%} | {vol} | {invol} |")
PY
