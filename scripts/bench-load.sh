#!/usr/bin/env bash
# Load benchmark: the release server under wrk (REST) and h2load (gRPC) on the paper's
# "Get the vase.", beside a floor (examples/floor.rs: same request/response types, no engine),
# at concurrency 1, 16 and 64; RSS sampled under load. Prints a Markdown table for BENCHMARKS.md.
# Installs wrk and h2load (Debian's nghttp2-client) when missing. Traffic stays on 127.0.0.1.
# Usage: scripts/bench-load.sh [SECONDS per run, default 10]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
seconds=${1:-10}
if ! command -v wrk >/dev/null || ! command -v h2load >/dev/null; then
  apt-get update -qq && apt-get install -y -qq wrk nghttp2-client >/dev/null
fi
cargo build --release --quiet --bin scruple --example floor --example grpc_body
work=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT

start() { # name, command...: starts a server, echoes its address
  local name=$1; shift
  "$@" >"$work/$name.out" 2>"$work/$name.err" &
  pids+=($!)
  echo $! >"$work/$name.pid"
  listening_addr "$work/$name.out" || true
}
scruple=$(start scruple target/release/scruple serve --listen 127.0.0.1:0 --database-url "sqlite://$work/bench.db")
floor=$(start floor target/release/examples/floor 127.0.0.1:0)
python3 - "$scruple" "$work" <<'PY'
import json, sys, urllib.request
addr, work = sys.argv[1], sys.argv[2]
demo = json.load(open("../shared/scenarios/paper-demo.json"))
for norm in demo["norms"]:
    urllib.request.urlopen(urllib.request.Request(f"http://{addr}/v1/norms", json.dumps(norm).encode(), {"content-type": "application/json"}))
body = {"directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."}, "scene": demo["scenes"]["lab"]}
open(f"{work}/body.json", "w").write(json.dumps(body))
answer = json.load(urllib.request.urlopen(urllib.request.Request(f"http://{addr}/v1/clarify", json.dumps(body).encode(), {"content-type": "application/json"})))
assert answer["decision"] == "assume", answer
PY
target/release/examples/grpc_body "$work/body.grpc"
cat >"$work/post.lua" <<LUA
wrk.method = "POST"
wrk.headers["content-type"] = "application/json"
local f = io.open("$work/body.json"); wrk.body = f:read("*a"); f:close()
LUA

rss_peak() { # pid: samples VmRSS every 0.2 s into $work/rss.<pid> until killed
  while kill -0 "$1" 2>/dev/null; do awk '/VmRSS/ {print $2}' "/proc/$1/status" >>"$work/rss.$1" 2>/dev/null || true; sleep 0.2; done
}
rss_peak "$(cat "$work/scruple.pid")" & pids+=($!)

wrk_run() { # addr, concurrency -> "rps p50 p99 errors"
  local threads=$(( $2 < 2 ? 1 : 2 ))
  wrk -t"$threads" -c"$2" -d"${seconds}s" --latency -s "$work/post.lua" "http://$1/v1/clarify" >"$work/wrk.txt"
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

echo "| transport | concurrency | Scruple req/s | floor req/s | ratio | Scruple p50 ms | Scruple p99 ms | floor p99 ms | errors |"
echo "|---|---|---|---|---|---|---|---|---|"
h2_run() { # addr, concurrency -> "rps p50 p99 failed"
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
compare() { # label, runner: one table row per concurrency, Scruple beside the floor
  for c in 1 16 64; do
    read -r s_rps s_p50 s_p99 s_err <<<"$("$2" "$scruple" "$c")"
    read -r f_rps _ f_p99 f_err <<<"$("$2" "$floor" "$c")"
    ratio=$(python3 -c "print(f'{$s_rps / $f_rps:.2f}')")
    echo "| $1 | $c | $s_rps | $f_rps | $ratio | $s_p50 | $s_p99 | $f_p99 | $((s_err + f_err)) |"
  done
}
compare "REST (wrk)" wrk_run
compare "gRPC (h2load)" h2_run
peak=$(sort -n "$work/rss.$(cat "$work/scruple.pid")" | tail -1)
echo
echo "Scruple peak RSS under load: $((peak / 1024)) MiB ($peak KiB)."
