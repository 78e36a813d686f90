#!/usr/bin/env bash
# The profile-guided release build of the server: what deploy/Dockerfile ships (BENCHMARKS.md,
# seventeenth sitting, for what it buys against `cargo build --release`). Reads only the build's
# sources, scripts/, examples/grpc_body.rs and tests/golden/corpus.jsonl (the image's context
# holds these and no more). Three steps, the server's two builds each in its own target dir
# (RUSTFLAGS differ, so nothing is shared with target/release):
#  1. the server built instrumented (-Cprofile-generate) and trained on 127.0.0.1: every request
#     of tests/golden/corpus.jsonl (every decision kind, reason and error; setups applied in turn,
#     statuses not checked) TRAIN_ROUNDS times; then wrk cycling through the corpus's
#     /v1/clarify bodies (structured ones, ones as text, ones that end in errors) for
#     TRAIN_SECONDS; then on gRPC every corpus /v1/clarify body that examples/grpc_body converts,
#     20 times each, and h2load on the paper's "Get the vase." for TRAIN_SECONDS (concurrency 16);
#  2. the server stopped with SIGINT (it drains and exits, writing its profile), the profile
#     merged with the toolchain's llvm-profdata (rustup's llvm-tools component, added if missing);
#  3. the server built again with -Cprofile-use, copied to OUT.
# Cold on 2 cores: two release builds of the server and a debug one of grpc_body (22 min on an
# Intel Xeon, BENCHMARKS.md, seventeenth sitting; a second run reuses the instrumented build's
# dependencies: 14 min). Installs wrk, h2load and Python 3 from Debian's packages when missing.
# `--train BINARY` runs only step 1's training against BINARY (CI does, on the debug server, so a
# change to the corpus or to grpc_body that breaks the image's build fails there) and fails if
# any part of it sent nothing or could not connect.
# Usage: [TRAIN_ROUNDS=3] [TRAIN_SECONDS=8] scripts/pgo-build.sh [OUT, default target/pgo/scruple]
#        [TRAIN_ROUNDS=1] [TRAIN_SECONDS=2] scripts/pgo-build.sh --train BINARY
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
train_only=""
if [ "${1:-}" = "--train" ]; then
  train_only=${2:?usage: scripts/pgo-build.sh --train BINARY}
fi
out=${1:-target/pgo/scruple}  # unused with --train
rounds=${TRAIN_ROUNDS:-3}
seconds=${TRAIN_SECONDS:-8}
need_tools wrk h2load python3
profdata() { find "$(rustc --print sysroot)/lib/rustlib" -name llvm-profdata -type f 2>/dev/null | head -1; }
# With --target, RUSTFLAGS reach only what is built for it: build scripts and proc macros are
# neither instrumented (their runs would write profiles of their own) nor built twice.
host=$(rustc -vV | sed -n 's/^host: //p')
work=$(mktemp -d)
server=""
cleanup() { if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; fi; rm -rf "$work"; }
trap cleanup EXIT

# train BINARY: step 1's load on BINARY, started on a fresh SQLite store; leaves it running in $server.
train() {
  "$1" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/train.db" >"$work/out" 2>"$work/err" &
  server=$!
  addr=$(listening_addr "$work/out") || { cat "$work/err" >&2; exit 1; }
  python3 - "$addr" "$work" "$rounds" <<'PY'
import json, os, sys, urllib.error, urllib.request
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
# wrk's Lua: one body after another, from a file of JSON bodies one a line; each body also as a
# file of its own for grpc_body, the paper's "Get the vase." (the load benchmark's case) as vase.json.
bodies = [json.dumps(e["request"]["body"]) for e in corpus
          if e["request"].get("path") == "/v1/clarify" and e["request"].get("method") == "POST" and "body" in e["request"]]
assert bodies, "no /v1/clarify bodies in tests/golden/corpus.jsonl"
with open(f"{work}/bodies.txt", "w") as f:
    f.write("\n".join(bodies) + "\n")
os.makedirs(f"{work}/rest")
for i, body in enumerate(bodies):
    open(f"{work}/rest/{i:04}.json", "w").write(body)
vase = {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."}
vases = [b for b in bodies if json.loads(b).get("directive") == vase]
assert vases, "no structured \"Get the vase.\" in tests/golden/corpus.jsonl"
open(f"{work}/vase.json", "w").write(vases[0])
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
  wrk -t2 -c16 -d"${seconds}s" -s "$work/cycle.lua" "http://$addr/v1/clarify" >"$work/wrk.txt"
  grep -E 'Requests/sec|Non-2xx' "$work/wrk.txt"
  grep -qE '^ +[0-9]+ requests in' "$work/wrk.txt" || { echo "pgo-build: wrk sent nothing" >&2; cat "$work/wrk.txt" >&2; exit 1; }
  mkdir "$work/grpc"
  local converted=0 total=0 body
  for body in "$work"/rest/*.json; do
    total=$((total + 1))
    # Bodies that are not valid requests (the corpus's error cases) may not convert: skipped.
    if "$grpc_body" "$body" "$work/grpc/$(basename "$body" .json).grpc" 2>/dev/null; then
      converted=$((converted + 1))
    fi
  done
  "$grpc_body" "$work/vase.json" "$work/vase.grpc"
  echo "gRPC: $converted of $total bodies converted"
  [ "$converted" -gt 0 ] || { echo "pgo-build: grpc_body converted no corpus body" >&2; exit 1; }
  for body in "$work"/grpc/*.grpc "$work/vase.grpc"; do
    local duration=(-n 20 -c 1)
    [ "$body" = "$work/vase.grpc" ] && duration=(-D "$seconds" -c 16)
    h2load "${duration[@]}" -m 1 -H 'content-type: application/grpc' -H 'te: trailers' \
      -d "$body" "http://$addr/scruple.v1.Clarifier/Clarify" >"$work/h2.txt"
    grep -qE 'requests: [0-9]+ total, [0-9]+ started, [0-9]+ done, [1-9][0-9]* succeeded' "$work/h2.txt" \
      || { echo "pgo-build: h2load: no gRPC call succeeded with $body" >&2; cat "$work/h2.txt" >&2; exit 1; }
  done
  grep -E 'finished in|requests:' "$work/h2.txt"
}

# grpc_body is an ordinary debug build (not instrumented: its own profile would be merged).
cargo build --locked --quiet --example grpc_body
grpc_body=target/debug/examples/grpc_body
if [ -n "$train_only" ]; then
  echo "== training $train_only"
  train "$train_only"
  kill -INT "$server"
  wait "$server" || { echo "pgo-build: $train_only did not exit cleanly after SIGINT" >&2; exit 1; }
  server=""
  echo "pgo-build: training ran"
  exit 0
fi
if [ -z "$(profdata)" ]; then
  rustup component add llvm-tools
fi
[ -n "$(profdata)" ] || { echo "pgo-build: no llvm-profdata in $(rustc --print sysroot) after adding llvm-tools" >&2; exit 1; }

# RUSTFLAGS are part of what cargo caches a build by. The instrumented build's flags name a fixed
# directory, so a later run (or the image's cache mount) reuses its dependencies; the optimised
# build's name the profile by its digest, so a new profile rebuilds every dependency (cargo does
# not look at a registry crate's inputs again, and their layout must follow the profile).
profiles=$PWD/target/pgo-generate/profiles
rm -rf "$profiles"

echo "== 1. instrumented build"
RUSTFLAGS="-Cprofile-generate=$profiles" \
  cargo build --release --locked --quiet --bin scruple --target "$host" --target-dir target/pgo-generate

echo "== 1. training"
train "target/pgo-generate/$host/release/scruple"

echo "== 2. profile"
kill -INT "$server"
wait "$server" || { echo "pgo-build: the instrumented server did not exit cleanly; its profile may be partial" >&2; exit 1; }
server=""
"$(profdata)" merge -o "$work/merged.profdata" "$profiles"
mkdir -p target/pgo-use
rm -f target/pgo-use/merged-*.profdata
merged=$PWD/target/pgo-use/merged-$(sha256sum "$work/merged.profdata" | cut -c1-16).profdata
mv "$work/merged.profdata" "$merged"
ls -l "$merged"

echo "== 3. optimised build"
RUSTFLAGS="-Cprofile-use=$merged" \
  cargo build --release --locked --quiet --bin scruple --target "$host" --target-dir target/pgo-use
install -D -m 0755 "target/pgo-use/$host/release/scruple" "$out"
echo "pgo-build: $out"
