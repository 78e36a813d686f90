# Sourced by the scripts beside it; runs nothing by itself.

# listening_addr OUT: waits up to 10 s for `scruple serve`'s `listening on ADDR` line in the file
# OUT (its stdout) and prints ADDR; status 1, printing nothing, when no such line came.
listening_addr() {
  local out=$1 addr
  for _ in $(seq 1 100); do grep -q '^listening on ' "$out" 2>/dev/null && break; sleep 0.1; done
  addr=$(sed -n 's/^listening on //p' "$out")
  [ -n "$addr" ] && echo "$addr"
}
