# Sourced by the scripts beside it; runs nothing by itself.

# need_tools COMMAND...: installs from Debian's packages whichever of the commands is missing
# (h2load comes in nghttp2-client; wrk and python3 in packages of their own names).
need_tools() {
  local missing=() tool
  for tool in "$@"; do
    command -v "$tool" >/dev/null && continue
    case $tool in
      h2load) missing+=(nghttp2-client) ;;
      *) missing+=("$tool") ;;
    esac
  done
  if [ ${#missing[@]} -gt 0 ]; then
    apt-get update -qq && apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

# listening_addr OUT: waits up to 10 s for `scruple serve`'s `listening on ADDR` line in the file
# OUT (its stdout) and prints ADDR; status 1, printing nothing, when no such line came.
listening_addr() {
  local out=$1 addr
  for _ in $(seq 1 100); do grep -q '^listening on ' "$out" 2>/dev/null && break; sleep 0.1; done
  addr=$(sed -n 's/^listening on //p' "$out")
  [ -n "$addr" ] && echo "$addr"
}

# paper_wrk WORK structured|text ADDR...: stores the paper's norms on each server at ADDR and
# writes WORK/body.json (the paper's "Get the vase." in the lab scene, the directive structured
# or as text) and WORK/body.lua (wrk posting it), for the load scripts beside this one.
paper_wrk() {
  python3 - "$@" <<'PY'
import json, sys, urllib.request
work, body, *addrs = sys.argv[1:]
demo = json.load(open("../shared/scenarios/paper-demo.json"))
for addr in addrs:
    for norm in demo["norms"]:
        urllib.request.urlopen(urllib.request.Request(f"http://{addr}/v1/norms", json.dumps(norm).encode(), {"content-type": "application/json"}))
directive = {"text": "Get the vase."}
if body == "structured":
    directive = {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."}
open(f"{work}/body.json", "w").write(json.dumps({"directive": directive, "scene": demo["scenes"]["lab"]}))
open(f"{work}/body.lua", "w").write(f'wrk.method = "POST"\nwrk.headers["content-type"] = "application/json"\n'
                                    f'local f = io.open("{work}/body.json"); wrk.body = f:read("*a"); f:close()\n')
PY
}
