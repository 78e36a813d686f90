#!/usr/bin/env bash
# Load benchmark: the release server under wrk (REST, the directive sent structured and sent as
# text) and h2load (gRPC) on the paper's "Get the vase.", beside a floor (examples/floor.rs: same
# request/response types, no engine; its REST answer to each body is Scruple's, byte for byte,
# checked before the runs), at each concurrency of $CONCURRENCY (default "1 16 64").
# Each row is $ROUNDS rounds (default 3) of Scruple then the floor, in turn; it shows the medians
# and the median of the rounds' ratios. RSS sampled under load. Prints a Markdown table for
# BENCHMARKS.md. Installs wrk and h2load (Debian's nghttp2-client) when missing. Traffic stays on
# 127.0.0.1. $SCRUPLE_BIN names another server binary to measure (default the release build;
# target/pgo/scruple after scripts/pgo-build.sh is what the image ships). gRPC's body is REST's
# structured one, converted by examples/grpc_body.
# Usage: scripts/bench-load.sh [SECONDS per run, default 10]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
seconds=${1:-10}
rounds=${ROUNDS:-3}
concurrency=${CONCURRENCY:-1 16 64}
floor_kind=${FLOOR:-typed}
case $floor_kind in
  typed) floor_args=() ;;
  value) floor_args=(--value) ;;
  *) echo "bench-load: FLOOR is typed or value, not $floor_kind" >&2; exit 2 ;;
esac
need_tools wrk h2load
# The server alone first: built with the examples, its dependencies' features would be unified
# with the dev-dependencies', and it would not be the binary `cargo build --release` makes: its
# symbols' hashes would differ, and link/hot-text.ld names a generic's instances by theirs.
cargo build --release --quiet --bin scruple
cargo build --release --quiet --example floor --example grpc_body
work=$(mktemp -d)
pids=()
# The servers start in `$(...)`, a subshell, so their pids are read back from their files.
cleanup() { for p in "${pids[@]}" $(cat "$work"/*.pid 2>/dev/null); do kill "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT

start() { # name, command...: starts a server, echoes its address
  local name=$1; shift
  "$@" >"$work/$name.out" 2>"$work/$name.err" &
  pids+=($!)
  echo $! >"$work/$name.pid"
  listening_addr "$work/$name.out" || true
}
scruple=$(start scruple "${SCRUPLE_BIN:-target/release/scruple}" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/bench.db")
floor=$(start floor target/release/examples/floor 127.0.0.1:0 "${floor_args[@]}")
python3 - "$scruple" "$work" "$floor" <<'PY'
import json, sys, urllib.request
addr, work, floor = sys.argv[1], sys.argv[2], sys.argv[3]
demo = json.load(open("../shared/scenarios/paper-demo.json"))
for norm in demo["norms"]:
    urllib.request.urlopen(urllib.request.Request(f"http://{addr}/v1/norms", json.dumps(norm).encode(), {"content-type": "application/json"}))
bodies = {
    "structured": {"directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."}, "scene": demo["scenes"]["lab"]},
    "text": {"directive": {"text": "Get the vase."}, "scene": demo["scenes"]["lab"]},
}
for name, body in bodies.items():
    open(f"{work}/{name}.json", "w").write(json.dumps(body))
    ask = lambda at: urllib.request.urlopen(urllib.request.Request(f"http://{at}/v1/clarify", json.dumps(body).encode(), {"content-type": "application/json"})).read()
    answer = ask(addr)
    assert json.loads(answer)["decision"] == "assume", answer
    # Like for like: the floor answers each body with Scruple's bytes.
    floors = ask(floor)
    assert floors == answer, f"the floor's answer to the {name} body is not Scruple's:\n{floors}\n{answer}"
PY
target/release/examples/grpc_body "$work/structured.json" "$work/body.grpc"
for body in structured text; do
  cat >"$work/$body.lua" <<LUA
wrk.method = "POST"
wrk.headers["content-type"] = "application/json"
local f = io.open("$work/$body.json"); wrk.body = f:read("*a"); f:close()
LUA
done

rss_peak() { # pid: samples VmRSS every 0.2 s into $work/rss.<pid> until killed
  while kill -0 "$1" 2>/dev/null; do awk '/VmRSS/ {print $2}' "/proc/$1/status" >>"$work/rss.$1" 2>/dev/null || true; sleep 0.2; done
}
rss_peak "$(cat "$work/scruple.pid")" & pids+=($!)

wrk_run() { # addr, concurrency, body -> "rps p50 p99 errors"
  local threads=$(( $2 < 2 ? 1 : 2 ))
  wrk -t"$threads" -c"$2" -d"${seconds}s" --latency -s "$work/$3.lua" "http://$1/v1/clarify" >"$work/wrk.txt"
  python3 - "$work/wrk.txt" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
def ms(v):
    found = re.match(r"([\d.]+)(us|ms|s|m)", v)
    if not found:
        sys.exit(f"cannot read the latency {v!r} in:\n{text}")
    n, unit = found.groups()
    return float(n) * {"us": 0.001, "ms": 1, "s": 1000, "m": 60000}[unit]
rps = float(re.search(r"Requests/sec:\s+([\d.]+)", text).group(1))
p50 = ms(re.search(r"^\s+50%\s+(\S+)", text, re.M).group(1))
p99 = ms(re.search(r"^\s+99%\s+(\S+)", text, re.M).group(1))
errors = sum(int(n) for n in re.findall(r"(?:Non-2xx or 3xx responses|Socket errors: connect) (\d+)", text))
print(f"{rps:.0f} {p50:.2f} {p99:.2f} {errors}")
PY
}

echo "Floor: $floor_kind (REST)."
echo
echo "| transport | concurrency | Scruple req/s | floor req/s | ratio (median of $rounds) | Scruple p50 ms | Scruple p99 ms | floor p99 ms | p99 ratio | errors |"
echo "|---|---|---|---|---|---|---|---|---|---|"
h2_run() { # addr, concurrency, (unused) -> "rps p50 p99 failed"
  h2load -D "$seconds" -c "$2" -m 1 -H 'content-type: application/grpc' -H 'te: trailers' \
    --log-file "$work/h2.log" -d "$work/body.grpc" "http://$1/scruple.v1.Clarifier/Clarify" >"$work/h2.txt"
  python3 - "$work/h2.txt" "$work/h2.log" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
rps = float(re.search(r"finished in [\d.]+\w+, ([\d.]+) req/s", text).group(1))
failed = int(re.search(r"(\d+) failed", text).group(1))
durations = sorted(int(line.split("\t")[2]) for line in open(sys.argv[2]) if line.strip())
pick = lambda q: durations[min(len(durations) - 1, int(q * len(durations)))] / 1000
print(f"{rps:.0f} {pick(0.50):.2f} {pick(0.99):.2f} {failed}")
PY
}
compare() { # label, runner, body: one row per concurrency, Scruple and the floor in turn
  for c in $concurrency; do
    : >"$work/rounds"
    for _ in $(seq 1 "$rounds"); do
      echo "$("$2" "$scruple" "$c" "$3") $("$2" "$floor" "$c" "$3")" >>"$work/rounds"
    done
    python3 - "$1" "$c" "$work/rounds" <<'PY'
import statistics as st, sys
label, c, path = sys.argv[1], sys.argv[2], sys.argv[3]
rows = [list(map(float, line.split())) for line in open(path)]
med = lambda i: st.median(r[i] for r in rows)
ratio = st.median(r[0] / r[4] for r in rows)
p99_ratio = st.median(r[2] / r[6] if r[6] else float("inf") for r in rows)
errors = int(sum(r[3] + r[7] for r in rows))
print(f"| {label} | {c} | {med(0):.0f} | {med(4):.0f} | {ratio:.2f} | {med(1):.2f} | {med(2):.2f} | {med(6):.2f} | {p99_ratio:.2f} | {errors} |")
PY
  done
}
compare "REST (wrk), structured" wrk_run structured
compare "REST (wrk), as text" wrk_run text
compare "gRPC (h2load)" h2_run structured
peak=$(sort -n "$work/rss.$(cat "$work/scruple.pid")" | tail -1)
echo
echo "Scruple peak RSS under load: $((peak / 1024)) MiB ($peak KiB)."
