#!/usr/bin/env bash
# A profile-guided release build of the server, to measure the lever (BENCHMARKS.md): not what
# `cargo build --release` or the Docker image ship. Three steps, the server's two builds each in
# its own target dir (RUSTFLAGS differ, so nothing is shared with target/release):
#  1. the server built instrumented (-Cprofile-generate) and trained on 127.0.0.1: every request
#     of tests/golden/corpus.jsonl (every decision kind, reason and error; setups applied in turn,
#     statuses not checked) TRAIN_ROUNDS times, then load spread over the transports the service
#     serves: wrk cycling through the corpus's /v1/clarify bodies (structured ones, ones as text,
#     ones that end in errors) and h2load on gRPC (the paper's "Get the vase.", the one gRPC body
#     examples/grpc_body writes), TRAIN_SECONDS each at concurrency 16;
#  2. the server stopped with SIGINT (it drains and exits, writing its profile), the profile
#     merged with the toolchain's llvm-profdata (rustup's llvm-tools component, added if missing);
#  3. the server built again with -Cprofile-use, copied to OUT.
# Cold on 2 cores: three release builds (26 min on a slow machine, BENCHMARKS.md, sixteenth
# sitting). Installs wrk and h2load when missing; needs Python 3 and ../shared (examples/grpc_body).
# Usage: [TRAIN_ROUNDS=3] [TRAIN_SECONDS=8] scripts/pgo-build.sh [OUT, default target/pgo/scruple]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
out=${1:-target/pgo/scruple}
rounds=${TRAIN_ROUNDS:-3}
seconds=${TRAIN_SECONDS:-8}
if ! command -v wrk >/dev/null || ! command -v h2load >/dev/null; then
  apt-get update -qq && apt-get install -y -qq wrk nghttp2-client >/dev/null
fi
profdata() { find "$(rustc --print sysroot)/lib/rustlib" -name llvm-profdata -type f 2>/dev/null | head -1; }
if [ -z "$(profdata)" ]; then
  rustup component add llvm-tools
fi
[ -n "$(profdata)" ] || { echo "pgo-build: no llvm-profdata in $(rustc --print sysroot) after adding llvm-tools" >&2; exit 1; }
# With --target, RUSTFLAGS reach only what is built for it: build scripts and proc macros are
# neither instrumented (their runs would write profiles of their own) nor built twice.
host=$(rustc -vV | sed -n 's/^host: //p')
work=$(mktemp -d)
server=""
cleanup() { if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; fi; rm -rf "$work"; }
trap cleanup EXIT

echo "== 1. instrumented build"
# The gRPC body comes from an ordinary release build of the example (not instrumented: its own
# profile would be merged with the server's).
cargo build --release --locked --quiet --example grpc_body
target/release/examples/grpc_body "$work/body.grpc"
RUSTFLAGS="-Cprofile-generate=$work/profiles" \
  cargo build --release --locked --quiet --bin scruple --target "$host" --target-dir target/pgo-generate

echo "== 1. training"
"target/pgo-generate/$host/release/scruple" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/train.db" \
  >"$work/out" 2>"$work/err" &
server=$!
addr=$(listening_addr "$work/out") || { cat "$work/err" >&2; exit 1; }
python3 - "$addr" "$work" "$rounds" <<'PY'
import json, sys, urllib.error, urllib.request
addr, work, rounds = sys.argv[1], sys.argv[2], int(sys.argv[3])
corpus = [json.loads(line) for line in open("tests/golden/corpus.jsonl")]
def send(req):
    data, headers = None, dict(req.get("headers", {}))
    if "body" in req:
        data = json.dumps(req["body"]).encode()
        headers.setdefault("content-type", "application/json")
    elif "raw" in req:
        data = req["raw"].encode()
    try:
        urllib.request.urlopen(urllib.request.Request(f"http://{addr}{req['path']}", data, headers, method=req["method"])).read()
    except urllib.error.HTTPError as e:
        e.read()
sent = 0
for _ in range(rounds):
    for entry in corpus:
        for req in entry.get("setup", []) + [entry["request"]]:
            send(req)
            sent += 1
print(f"corpus: {sent} requests ({len(corpus)} entries x {rounds})")
# wrk's Lua: one body after another, from a file of JSON bodies one a line.
bodies = [json.dumps(e["request"]["body"]) for e in corpus
          if e["request"].get("path") == "/v1/clarify" and e["request"].get("method") == "POST" and "body" in e["request"]]
with open(f"{work}/bodies.txt", "w") as f:
    f.write("\n".join(bodies) + "\n")
open(f"{work}/cycle.lua", "w").write(f'''
local bodies = {{}}
for line in io.lines("{work}/bodies.txt") do bodies[#bodies + 1] = line end
local i = 0
request = function()
  i = i % #bodies + 1
  return wrk.format("POST", "/v1/clarify", {{["content-type"] = "application/json"}}, bodies[i])
end
''')
print(f"load: {len(bodies)} /v1/clarify bodies in turn")
PY
wrk -t2 -c16 -d"${seconds}s" -s "$work/cycle.lua" "http://$addr/v1/clarify" | grep -E 'Requests/sec|Non-2xx' || true
h2load -D "$seconds" -c 16 -m 1 -H 'content-type: application/grpc' -H 'te: trailers' \
  -d "$work/body.grpc" "http://$addr/scruple.v1.Clarifier/Clarify" | grep -E 'finished in|requests:' || true

echo "== 2. profile"
kill -INT "$server"
wait "$server" || { echo "pgo-build: the instrumented server did not exit cleanly; its profile may be partial" >&2; exit 1; }
server=""
"$(profdata)" merge -o "$work/merged.profdata" "$work/profiles"
ls -l "$work/merged.profdata"

echo "== 3. optimised build"
RUSTFLAGS="-Cprofile-use=$work/merged.profdata" \
  cargo build --release --locked --quiet --bin scruple --target "$host" --target-dir target/pgo-use
install -D -m 0755 "target/pgo-use/$host/release/scruple" "$out"
echo "pgo-build: $out"
