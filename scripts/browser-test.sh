#!/usr/bin/env bash
# The playground in Debian's Chromium, driven by playwright-core, against real `scruple serve`s
# on fresh databases: tests/browser/playground.mjs (the paper's case, norms, readings; saves a
# screenshot, default docs/playground.png), then tests/browser/dialogue.mjs (a conversation, its
# transcript exported and reloaded, people, roles, verbs; a second service with reader tokens;
# saves a screenshot of the dialogue, default beside the first as dialogue.png); then the HTML
# report of an experiment (`scruple replay --conditions ... --report`) opened from its file by
# tests/browser/report.mjs (its chart and tables drawn, nothing fetched; a screenshot, default
# beside the first as replay-report.png).
# Usage: scripts/browser-test.sh [path/to/scruple] [screenshot.png] [dialogue.png] [report.png]
# Needs node and npm; installs chromium with apt-get when /usr/bin/chromium is missing (as root).
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
bin=${1:-${CARGO_TARGET_DIR:-target}/debug/scruple}
shot=$(realpath -m "${2:-docs/playground.png}")
dialogue_shot=$(realpath -m "${3:-$(dirname "$shot")/dialogue.png}")
report_shot=$(realpath -m "${4:-$(dirname "$shot")/replay-report.png}")
# The tokens of the second service: a reader's and an admin's (each secret distinct: the service
# refuses to start with two tokens of the same secret).
reader_token=0123456789abcdef0123
admin_token=fedcba9876543210fedc
work=$(mktemp -d)
servers=()
cleanup() {
  for pid in "${servers[@]}"; do kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; done
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

# serve NAME [FLAG...]: a server on a fresh database of its own; sets $addr.
serve() {
  local name=$1
  shift
  "$bin" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/$name.db" "$@" >"$work/$name.out" 2>"$work/$name.err" &
  servers+=($!)
  addr=$(listening_addr "$work/$name.out") || fail "$name: no 'listening on' line; stderr: $(cat "$work/$name.err")"
  echo "browser-test: $name server on $addr"
}

serve playground
node tests/browser/playground.mjs "http://$addr/" "$shot" || fail "the playground test failed"

serve dialogue
plain=$addr
serve tokens --reader-token "r=$reader_token" --admin-token "$admin_token"
READER_TOKEN=$reader_token ADMIN_TOKEN=$admin_token \
  node tests/browser/dialogue.mjs "http://$plain/" "$dialogue_shot" "http://$addr/" || fail "the dialogue test failed"

# The README's experiment: the paper's directives under three conditions, as a page.
"$bin" replay examples/replay/directives.jsonl --scene examples/scenes/lab.json --norms examples/norms/paper.json \
  --conditions-file examples/replay/conditions.json --out "$work/answers.jsonl" --report "$work/report.html" \
  2>"$work/replay.err" || fail "the experiment's replay failed: $(cat "$work/replay.err")"
node tests/browser/report.mjs "$work/report.html" "$work/answers.jsonl" "$report_shot" || fail "the report test failed"

# Each server drains and exits 0 on SIGTERM.
for pid in "${servers[@]}"; do
  kill -TERM "$pid"
  wait "$pid" && status=0 || status=$?
  [ "$status" = 0 ] || fail "a server exited $status on SIGTERM"
done
servers=()
