#!/usr/bin/env bash
# Heavy load, the part that is correctness: CLIENTS clients each sending 316 cups x 316 plates
# (99,856 readings, the default 2 s deadline) for SECONDS against the release server on
# 127.0.0.1, with /healthz probed every 100 ms and the paper's "Get the vase." asked every 20 ms
# (examples/heavy_load.rs). Passes when every answer comes within its deadline + 250 ms (or is a
# 503 overloaded), none is norms-unavailable, health's p99 is within 50 ms, the light requests'
# p99 within 250 ms, and the server's RSS 10 s after the burst within twice its idle RSS.
# Bounded: it stops by itself after SECONDS (and 10 s more).
# Usage: scripts/heavy-load.sh [CLIENTS, default 64] [SECONDS, default 30] [BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
clients=${1:-64}
seconds=${2:-30}
binary=${3:-target/release/scruple}
if [ "$binary" = target/release/scruple ]; then
  # Apart, so the server is the one `cargo build --release` makes (scripts/bench-load.sh says why).
  cargo build --release --quiet --bin scruple
  cargo build --release --quiet --example heavy_load
  generator=target/release/examples/heavy_load
else
  cargo build --quiet --example heavy_load
  generator=target/debug/examples/heavy_load
fi
work=$(mktemp -d)
"$binary" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/heavy.db" >"$work/out" 2>"$work/err" &
server=$!
trap 'kill $server 2>/dev/null || true; rm -rf "$work"' EXIT
addr=$(listening_addr "$work/out") || { cat "$work/err" >&2; exit 1; }
rss() { awk '/VmRSS/ {print $2}' "/proc/$server/status"; }
# Idle: after one light request, so the runtime, the store and the caches are up.
curl -s -o /dev/null -X POST -H 'content-type: application/json' \
  -d '{"directive":{"action":"get","arguments":[{"type":"vase"}]},"scene":{"agent":{"position":[0,0,0.75]},"objects":[]}}' \
  "http://$addr/v1/clarify" || true
idle=$(rss)
status=0
"$generator" "$addr" "$clients" "$seconds" 316 2000 || status=$?
sleep 10
after=$(rss)
echo "  RSS: idle $((idle / 1024)) MiB, 10 s after the burst $((after / 1024)) MiB ($(python3 -c "print(f'{$after / $idle:.2f}')")x idle; within 2x: $([ "$after" -le $((2 * idle)) ] && echo yes || echo no))"
[ "$after" -le $((2 * idle)) ] || status=1
exit $status
