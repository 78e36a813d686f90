#!/usr/bin/env bash
# Server CPU per request, two server binaries in turn: each serves the paper's "Get the vase."
# (REST, the directive structured or as text) under wrk at concurrency 64, and its user and
# system CPU time (from /proc/PID/stat) is divided by the requests it answered. A measure of the
# work one request costs the server that moves less with the load beside it than throughput does
# on a shared machine (the load generator and the server share the cores either way). Traffic
# stays on 127.0.0.1; installs wrk when missing.
# Usage: scripts/cpu-per-request.sh BINARY_A BINARY_B [ROUNDS, default 4] [SECONDS, default 4] [structured|text]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
a=$1 b=$2 rounds=${3:-4} seconds=${4:-4} body=${5:-structured}
need_tools wrk
work=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT
start() { # name binary: starts a server with the paper's norms, echoes "pid addr"
  "$2" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/$1.db" >"$work/$1.out" 2>"$work/$1.err" &
  pids+=($!)
  echo "$! $(listening_addr "$work/$1.out")"
}
# `start` runs in a subshell here: the pids it adds are lost there, so they are added again.
read -r pid_a addr_a < <(start a "$a")
read -r pid_b addr_b < <(start b "$b")
pids+=("$pid_a" "$pid_b")
paper_wrk "$work" "$body" "$addr_a" "$addr_b"
measure() { # pid addr -> "user_us system_us requests_per_s"
  local u0 s0 u1 s1 rps
  read -r u0 s0 < <(awk '{print $14, $15}' "/proc/$1/stat")
  rps=$(wrk -t2 -c64 -d"${seconds}s" -s "$work/body.lua" "http://$2/v1/clarify" | awk '/Requests\/sec/ {print $2}')
  read -r u1 s1 < <(awk '{print $14, $15}' "/proc/$1/stat")
  python3 -c "
tick = $(getconf CLK_TCK); n = $rps * $seconds
print(f'{($u1 - $u0) / tick / n * 1e6:.1f} {($s1 - $s0) / tick / n * 1e6:.1f} {$rps:.0f}')"
}
echo "| round | A user+system µs/request | A req/s | B user+system µs/request | B req/s | B/A CPU |"
echo "|---|---|---|---|---|---|"
for round in $(seq 1 "$rounds"); do
  read -r ua sa ra < <(measure "$pid_a" "$addr_a")
  read -r ub sb rb < <(measure "$pid_b" "$addr_b")
  python3 -c "print(f'| $round | $ua+$sa | $ra | $ub+$sb | $rb | {($ub + $sb) / ($ua + $sa):.2f} |')"
done
