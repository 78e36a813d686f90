#!/usr/bin/env bash
# The built image, checked from outside as an operator runs it (needs a Docker engine; build the
# image first, deploy/README.md):
#  1. the container as the Dockerfile leaves it (`docker run -d -p 127.0.0.1::8080 IMAGE`, its
#     own /data volume): it runs as 10001:10001, answers every case of ../shared's
#     paper-demo.json structured and as text, keeps its database in /data owned by that user;
#     `docker stop` (SIGTERM to the entrypoint) drains and exits 0, and after `docker start` the
#     norms are still there;
#  2. scripts/smoke.sh with the image as its server (REST, gRPC by reflection, the admin token,
#     TLS, SIGTERM), the container on the host's network with smoke's folder mounted.
# Needs curl and python3 (and grpcurl for step 2, as smoke.sh says).
# Usage: scripts/image-check.sh [IMAGE, default scruple:0.1.0]
set -euo pipefail
cd "$(dirname "$0")/.."
image=${1:-scruple:0.1.0}
docker info >/dev/null 2>&1 || { echo "image-check: no Docker engine answers (docker info)" >&2; exit 2; }
docker image inspect "$image" >/dev/null 2>&1 || { echo "image-check: no image $image; build it first" >&2; exit 2; }
work=$(mktemp -d)
cid=""
cleanup() { [ -z "$cid" ] || docker rm -f -v "$cid" >/dev/null 2>&1 || true; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "image-check: FAIL: $*" >&2; [ -z "$cid" ] || docker logs "$cid" 2>&1 | tail -5 >&2; exit 1; }
ok() { echo "image-check: ok: $*"; }
healthy() { # waits up to 10 s for /healthz on $addr
  for _ in $(seq 1 100); do
    [ "$(curl -s -o /dev/null -w '%{http_code}' "http://$addr/healthz")" = 200 ] && return 0
    sleep 0.1
  done
  return 1
}

cid=$(docker run -d -p 127.0.0.1::8080 "$image")
addr=$(docker port "$cid" 8080/tcp | grep -m1 '^127.0.0.1:') || fail "no published port"
healthy || fail "/healthz did not answer 200 within 10 s"
ok "the container answers /healthz on $addr"
owner=$(docker top "$cid" -o pid,uid,gid | awk 'NR == 2 {print $2 ":" $3}')
[ "$owner" = 10001:10001 ] || fail "the server runs as $owner, not 10001:10001"
ok "the server runs as 10001:10001"
counts=$(python3 - "$addr" <<'PY'
import json, sys, urllib.request
addr = sys.argv[1]
demo = json.load(open("../shared/scenarios/paper-demo.json"))
def post(path, body):
    request = urllib.request.Request(f"http://{addr}{path}", json.dumps(body).encode(), {"content-type": "application/json"})
    return json.load(urllib.request.urlopen(request))
for norm in demo["norms"]:
    post("/v1/norms", norm)
wrong = []
for case in demo["cases"]:
    for form, directive in (("structured", dict(case["directive"], text=case["text"])), ("as text", {"text": case["text"]})):
        body = {"directive": directive, "scene": demo["scenes"][case["scene"]], **({"options": case["options"]} if "options" in case else {})}
        answer = post("/v1/clarify", body)
        wrong += [f"{case['name']} ({form}): {key} {answer.get(key)!r}, expected {value!r}"
                  for key, value in case["expect"].items() if answer.get(key) != value]
if wrong:
    sys.exit("\n".join(wrong))
print(len(demo["cases"]), len(demo["norms"]))
PY
) || fail "the paper's cases"
read -r cases stored <<<"$counts"
ok "all $cases paper cases, structured and as text"
docker cp "$cid:/data/." - | tar -tvf - >"$work/data"
grep -Eq '10001/10001 .* \./scruple\.db$' "$work/data" || fail "no scruple.db of 10001 in /data: $(cat "$work/data")"
ok "the norms are in /data/scruple.db, owned by 10001"
curl -s "http://$addr/v1/norms" >"$work/norms.before"
docker stop -t 10 "$cid" >/dev/null
status=$(docker inspect -f '{{.State.ExitCode}}' "$cid")
[ "$status" = 0 ] || fail "docker stop: exit status $status"
docker logs "$cid" 2>&1 | grep -q 'shutting down' || fail "no drain logged on SIGTERM"
ok "docker stop drains and exits 0"
docker start "$cid" >/dev/null
addr=$(docker port "$cid" 8080/tcp | grep -m1 '^127.0.0.1:') || fail "no published port after the restart"
healthy || fail "/healthz after the restart"
curl -s "http://$addr/v1/norms" >"$work/norms.after"
cmp -s "$work/norms.before" "$work/norms.after" || fail "the norms changed over the restart: $(cat "$work/norms.after")"
ok "after docker start the $stored norms are the same"
docker rm -f -v "$cid" >/dev/null
cid=""

# smoke.sh starts its server as a binary with serve's flags; this one runs the image instead, as
# the invoking user (smoke's files are that user's), on the host's network, smoke's folder mounted
# at the same path.
cat >"$work/server" <<SH
#!/bin/sh
db=\$(printf '%s\n' "\$@" | sed -n 's#^sqlite://##p')
folder=\$(dirname "\$db")
exec docker run --rm --network host --user "$(id -u):$(id -g)" -v "\$folder:\$folder" "$image" "\$@"
SH
chmod +x "$work/server"
scripts/smoke.sh "$work/server" || fail "scripts/smoke.sh against the image"
ok "scripts/smoke.sh passes with the image as its server"
echo "image-check: $image passed"
