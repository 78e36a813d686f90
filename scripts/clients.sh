#!/usr/bin/env bash
# Runs the client examples against a real `scruple serve`, each on a fresh database (every client
# adds the paper's norm, so each needs an empty norm set to get the same answer): the Python REST
# and gRPC clients in examples/python and the Rust gRPC client, examples/client.rs.
# Usage: scripts/clients.sh [path/to/scruple]   (default: target/debug/scruple; honours
# CARGO_TARGET_DIR). The Python requirements go into a venv kept at target/py-clients.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
target=${CARGO_TARGET_DIR:-target}
bin=${1:-$target/debug/scruple}
[ -x "$bin" ] || { echo "clients: no binary at $bin (cargo build first, or pass its path)" >&2; exit 1; }
work=$(mktemp -d)
server=""
stop_server() {
  if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; fi
  server=""
}
cleanup() { stop_server; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "clients: FAIL: $*" >&2; exit 1; }

venv=target/py-clients
if [ ! -x "$venv/bin/python" ]; then python3 -m venv "$venv"; fi
"$venv/bin/pip" install --quiet --disable-pip-version-check -r examples/python/requirements.txt
# Build the Rust client before any server starts, so a slow build cannot time a server out.
cargo build --quiet --example client

# Starts a server on a fresh database; sets `addr`.
start_server() {
  local name=$1
  "$bin" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/$name.db" >"$work/$name.out" 2>"$work/$name.err" &
  server=$!
  addr=$(listening_addr "$work/$name.out") || fail "$name: no 'listening on' line; stderr: $(cat "$work/$name.err")"
}

passed=0
run_client() {
  local name=$1; shift
  start_server "$name"
  echo "clients: $name against $addr"
  "$@" "$addr" || fail "$name"
  stop_server
  passed=$((passed + 1))
  echo "clients: ok: $name"
}

run_client python-http "$venv/bin/python" examples/python/http_client.py
# Twice, so that the second run imports the stubs the first generated into the venv's cache.
export SCRUPLE_STUBS_DIR=$venv/grpc-stubs
rm -rf "$SCRUPLE_STUBS_DIR"
run_client python-grpc "$venv/bin/python" examples/python/grpc_client.py
[ -n "$(ls "$SCRUPLE_STUBS_DIR")" ] || fail "python-grpc: no stubs kept in $SCRUPLE_STUBS_DIR"
run_client python-grpc-cached "$venv/bin/python" examples/python/grpc_client.py
run_client rust-grpc cargo run --quiet --example client --
echo "clients: $passed passed, 0 failed"
