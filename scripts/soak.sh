#!/usr/bin/env bash
# Load and soak of the release server on the paper's "Get the vase." (REST, HTTP/1.1):
#  1. load: exactly N requests (default 100,000) at concurrency 128 with h2load --h1; every answer
#     must be 200 (no 503 from admission control, no error);
#  2. soak: wrk at concurrency 32 for S seconds (default 600), the server's RSS sampled every 10 s;
#     fails unless every sample after the first minute is within 10% of that minute's sample.
# With SOAK_TLS=1 the server serves TLS (--tls-cert/--tls-key, a P-256 certificate made with
# openssl), both runs go over https, and a third step opens CHURN (default 5,000) fresh TLS
# connections one after another, a handshake and a request each, to show handshakes leave nothing.
# Prints Markdown for BENCHMARKS.md. Installs wrk and h2load (Debian) when missing.
# Usage: [SOAK_TLS=1] scripts/soak.sh [REQUESTS, default 100000] [SOAK SECONDS, default 600] [CHURN]
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
requests=${1:-100000}
soak=${2:-600}
churn=${3:-5000}
tls=${SOAK_TLS:-0}
need_tools wrk h2load
cargo build --release --quiet --bin scruple
work=$(mktemp -d)
server=""
cleanup() { if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; fi; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "soak: FAIL: $*" >&2; exit 1; }

scheme=http
tls_args=()
if [ "$tls" = 1 ]; then
  scheme=https
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -days 2 -subj /CN=localhost \
    -addext "subjectAltName=IP:127.0.0.1,DNS:localhost" -keyout "$work/tls.key" -out "$work/tls.crt" 2>/dev/null
  tls_args=(--tls-cert "$work/tls.crt" --tls-key "$work/tls.key")
fi
target/release/scruple serve --listen 127.0.0.1:0 --database-url "sqlite://$work/soak.db" "${tls_args[@]}" >"$work/out" 2>"$work/err" &
server=$!
addr=$(listening_addr "$work/out") || fail "no 'listening on' line: $(cat "$work/err")"
python3 - "$scheme://$addr" "$work" <<'PY'
import json, ssl, sys, urllib.request
base, work = sys.argv[1], sys.argv[2]
context = ssl.create_default_context(cafile=f"{work}/tls.crt") if base.startswith("https") else None
demo = json.load(open("../shared/scenarios/paper-demo.json"))
for norm in demo["norms"]:
    urllib.request.urlopen(urllib.request.Request(f"{base}/v1/norms", json.dumps(norm).encode(), {"content-type": "application/json"}), context=context)
body = {"directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."}, "scene": demo["scenes"]["lab"]}
open(f"{work}/body.json", "w").write(json.dumps(body))
PY
rss() { awk '/VmRSS/ {print $2}' "/proc/$server/status"; }

echo "## Load: $requests requests at concurrency 128 (h2load --h1, REST over $scheme)"
start_rss=$(rss)
h2load --h1 -n "$requests" -c 128 -m 1 -H 'content-type: application/json' -d "$work/body.json" \
  "$scheme://$addr/v1/clarify" >"$work/load.txt"
python3 - "$work/load.txt" "$requests" <<'PY'
import re, sys
text, wanted = open(sys.argv[1]).read(), int(sys.argv[2])
done = re.search(r"requests: (\d+) total, (\d+) started, (\d+) done, (\d+) succeeded, (\d+) failed, (\d+) errored, (\d+) timeout", text)
codes = re.search(r"status codes: (\d+) 2xx, (\d+) 3xx, (\d+) 4xx, (\d+) 5xx", text)
rate = re.search(r"finished in ([\d.]+\w+), ([\d.]+) req/s", text)
total, _, _, ok, failed, errored, timeout = map(int, done.groups())
c2, c3, c4, c5 = map(int, codes.groups())
print(f"- {total} requests in {rate.group(1)} ({float(rate.group(2)):.0f} req/s): {c2} × 2xx, {c4} × 4xx, {c5} × 5xx; {failed} failed, {errored} errored, {timeout} timed out")
for line in text.splitlines():
    if line.startswith("time for request:"):
        print(f"- {line.strip()} (min, max, mean, sd, ±sd)")
if c2 != wanted or failed or errored or timeout:
    sys.exit(f"soak: FAIL: not every request was answered 200:\n{text}")
PY
echo "- RSS before: $((start_rss / 1024)) MiB, after: $(( $(rss) / 1024 )) MiB"

echo
if [ "$tls" = 1 ]; then
  echo
  echo "## Handshake churn: $churn fresh TLS connections, one after another"
  before=$(rss)
  python3 - "$addr" "$work/tls.crt" "$churn" <<'PY'
import http.client, ssl, sys, time
addr, cafile, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
host, port = addr.rsplit(":", 1)
context = ssl.create_default_context(cafile=cafile)
ok, start = 0, time.monotonic()
for _ in range(n):
    connection = http.client.HTTPSConnection(host, int(port), context=context, timeout=10)
    connection.request("GET", "/healthz")
    ok += connection.getresponse().status == 200
    connection.close()
elapsed = time.monotonic() - start
print(f"- {n} connections in {elapsed:.1f} s ({n / elapsed:.0f}/s), {ok} × 200")
if ok != n:
    sys.exit("soak: FAIL: a fresh TLS connection was not served")
PY
  echo "- RSS before: $((before / 1024)) MiB, after: $(( $(rss) / 1024 )) MiB"
fi

echo
echo "## Soak: wrk at concurrency 32 for $soak s, RSS every 10 s (REST over $scheme)"
cat >"$work/post.lua" <<LUA
wrk.method = "POST"
wrk.headers["content-type"] = "application/json"
local f = io.open("$work/body.json"); wrk.body = f:read("*a"); f:close()
LUA
wrk -t2 -c32 -d"${soak}s" -s "$work/post.lua" "$scheme://$addr/v1/clarify" >"$work/wrk.txt" &
load=$!
: >"$work/rss"
elapsed=0
while kill -0 "$load" 2>/dev/null; do
  sleep 10
  elapsed=$((elapsed + 10))
  kill -0 "$load" 2>/dev/null && echo "$elapsed $(rss)" >>"$work/rss"
done
wait "$load"
python3 - "$work/rss" "$work/wrk.txt" <<'PY'
import re, sys
samples = [tuple(map(int, l.split())) for l in open(sys.argv[1]) if l.strip()]
text = open(sys.argv[2]).read()
rps = re.search(r"Requests/sec:\s+([\d.]+)", text).group(1)
total = re.search(r"(\d+) requests in", text).group(1)
errors = sum(int(n) for n in re.findall(r"(?:Non-2xx or 3xx responses|Socket errors: connect) (\d+)", text))
print(f"- {total} requests, {float(rps):.0f} req/s, {errors} errors")
print("- RSS (MiB) every 10 s: " + ", ".join(f"{kib / 1024:.1f}" for _, kib in samples))
settled = [kib for t, kib in samples if t >= 60]
if not settled:
    sys.exit("soak: FAIL: too short to judge; run at least 70 s")
base = settled[0]
spread = max(abs(k - base) / base for k in settled)
print(f"- after the first minute: min {min(settled) / 1024:.1f} MiB, max {max(settled) / 1024:.1f} MiB, largest drift from the 60 s sample {spread * 100:.1f}% (limit 10%)")
if errors or spread > 0.10:
    sys.exit("soak: FAIL: errors under load, or memory not flat")
PY
