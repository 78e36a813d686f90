#!/usr/bin/env bash
# Writes link/hot-text.ld, the order in which an ordinary `cargo build --release` lays out the
# server's hot functions (build.rs hands it to the linker; ARCHITECTURE.md, "The hot path's code
# layout"; BENCHMARKS.md, twenty-fifth sitting, for what it buys). Run it again after a change of
# dependencies or a large change of the request path (--check says when):
#  1. the release server built as `cargo build --release` builds it;
#  2. trained under callgrind (valgrind; Debian's package, installed when missing) with the
#     profile-guided build's own training (scripts/pgo-build.sh --train: the golden corpus, then
#     load on REST and gRPC), counting calls between the binary's functions;
#  3. scripts/hot-text.py orders the functions called at least 100 times and writes the script.
# About 10 minutes on 2 cores, most of it the build and the training under valgrind.
# `--check` (CI) builds the release server and fails unless its .text.hot section holds at least
# half of the functions the script names: a script gone stale (the dependencies' build metadata
# moved, the names of the hot functions changed) or a linker that ignored it.
# Usage: [TRAIN_ROUNDS=1] [TRAIN_SECONDS=4] scripts/hot-text.sh [--check]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
binary=$PWD/target/release/scruple
cargo build --release --locked --quiet --bin scruple

if [ "${1:-}" = "--check" ]; then
  named=$(grep -c '^    \*(\.text\.' link/hot-text.ld)
  # The section's bounds, then every function symbol within them.
  read -r start size < <(readelf -SW "$binary" | awk '{ for (i = 1; i < NF; i++) if ($i == ".text.hot") print $(i + 2), $(i + 4) }') || true
  [ -n "${start:-}" ] || { echo "hot-text: $binary has no .text.hot section: was link/hot-text.ld given to the linker?" >&2; exit 1; }
  laid=$(nm --defined-only "$binary" | python3 -c '
import sys
start, size = int(sys.argv[1], 16), int(sys.argv[2], 16)
print(sum(1 for line in sys.stdin if len(p := line.split()) == 3 and p[1] in "tTwW" and start <= int(p[0], 16) < start + size))
' "$start" "$size")
  echo "hot-text: .text.hot holds $laid functions, $((16#$size)) bytes; link/hot-text.ld names $named"
  if [ $((laid * 2)) -lt "$named" ]; then
    echo "hot-text: link/hot-text.ld is stale (fewer than half its functions found); run scripts/hot-text.sh" >&2
    exit 1
  fi
  exit 0
fi

need_tools valgrind python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The training starts the server by the name it is given: this one runs it under callgrind.
cat >"$work/under-callgrind" <<EOF
#!/bin/sh
exec valgrind --quiet --tool=callgrind --demangle=no --callgrind-out-file="$work/callgrind.out" "$binary" "\$@"
EOF
chmod +x "$work/under-callgrind"
TRAIN_ROUNDS=${TRAIN_ROUNDS:-1} TRAIN_SECONDS=${TRAIN_SECONDS:-4} scripts/pgo-build.sh --train "$work/under-callgrind"
nm -S --defined-only "$binary" >"$work/nm.txt"
python3 scripts/hot-text.py "$work/callgrind.out" "$work/nm.txt" scruple >"$work/hot-text.ld"
mkdir -p link
mv "$work/hot-text.ld" link/hot-text.ld
echo "hot-text: wrote link/hot-text.ld; cargo build --release lays the server out by it"
