#!/usr/bin/env bash
# Installs the Python client package (clients/python) into a fresh venv, as a user would, and runs
# its tests against a real `scruple serve` on a free port and a fresh SQLite store; the token
# tests start servers of their own from the same binary, and the chat example runs from
# examples/python. Exits with pytest's status.
# Usage: scripts/python-package.sh [path/to/scruple] [PYTEST ARGS...]   (default binary:
# target/debug/scruple; honours CARGO_TARGET_DIR). The venv is target/py-package, made afresh.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
target=${CARGO_TARGET_DIR:-target}
bin=${1:-$target/debug/scruple}
shift || true
[ -x "$bin" ] || { echo "python-package: no binary at $bin (cargo build first, or pass its path)" >&2; exit 1; }
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
work=$(mktemp -d)
server=""
stop_server() {
  if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; fi
  server=""
}
cleanup() { stop_server; rm -rf "$work"; }
trap cleanup EXIT

venv=$target/py-package
case $venv in /*) ;; *) venv=$PWD/$venv ;; esac
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check "./clients/python[test]"

"$bin" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/scruple.db" >"$work/out" 2>"$work/err" &
server=$!
addr=$(listening_addr "$work/out") || {
  echo "python-package: FAIL: no 'listening on' line; stderr: $(cat "$work/err")" >&2
  exit 1
}
echo "python-package: testing the installed scruple-client against $addr"

# The sources are under clients/python/src, off the path: `import scruple_client` is the
# package just installed.
status=0
(cd clients/python && SCRUPLE_URL="http://$addr" SCRUPLE_BIN="$bin" \
  "$venv/bin/python" -m pytest -p no:cacheprovider tests "$@") || status=$?
stop_server
exit "$status"
