#!/usr/bin/env bash
# The playground in Debian's Chromium, driven by playwright-core, against a real `scruple serve`
# on a fresh database. Saves a screenshot (default docs/playground.png).
# Usage: scripts/browser-test.sh [path/to/scruple] [screenshot.png]
# Needs node and npm; installs chromium with apt-get when /usr/bin/chromium is missing (as root).
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
bin=${1:-${CARGO_TARGET_DIR:-target}/debug/scruple}
shot=$(realpath -m "${2:-docs/playground.png}")
work=$(mktemp -d)
server=""
cleanup() {
  if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "browser-test: FAIL: $*" >&2; exit 1; }

[ -x "$bin" ] || fail "no scruple binary at $bin (build it, or pass its path)"
if [ ! -x /usr/bin/chromium ]; then
  echo "browser-test: installing chromium"
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; } >"$work/apt.log" 2>&1 \
    || fail "apt-get install chromium: $(tail -5 "$work/apt.log")"
fi
# The lock pins playwright-core; it brings no browser of its own, it drives /usr/bin/chromium.
(cd tests/browser && npm ci --no-audit --no-fund --loglevel=error) || fail "npm ci in tests/browser"

"$bin" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/browser.db" >"$work/out" 2>"$work/err" &
server=$!
addr=$(listening_addr "$work/out") || fail "no 'listening on' line; stderr: $(cat "$work/err")"
echo "browser-test: server on $addr"

node tests/browser/playground.mjs "http://$addr/" "$shot" || fail "the browser test failed"

kill -TERM "$server"
wait "$server" && status=0 || status=$?
server=""
[ "$status" = 0 ] || fail "the server exited $status on SIGTERM"
