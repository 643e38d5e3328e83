#!/usr/bin/env bash
# Soft shadows end to end on the project's own area-light room: dhr-xrclient (offscreen) offers soft levels
# because two of the scene's lights have an extent, dhr-server grants them and traces their levels, and the
# client presents every frame from them; against a server with --soft-levels off (one bit per light) the
# client refuses the session with a reason instead of reading bits as levels.
# Usage: client_soft_levels_cli.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/client_lib.sh" "$@"
scene="$src/assets/scenes/default_room_area.gltf"
export DHR_LOG=info

run_client() {  # name
  mkdir -p "$tmp/$1"
  "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --trace "$trace" \
    --offscreen "$tmp/$1" --eye-size 96x72 --frames 30 --png-every 0 --connect-timeout 2 \
    --stats-jsonl "$tmp/$1/stats.jsonl" >"$tmp/$1.out" 2>"$tmp/$1.err"
}

mkdir -p "$tmp/server1" "$tmp/server2"
start_server "$server_exe" "$scene" "$tmp/server1"
run_client granted || { tail -n 20 "$tmp/granted.err"; echo "FAIL: the soft-levels run"; exit 1; }
grep -q "3 lights (2 with soft levels)" "$server_tmp/server.log" ||
  { cat "$server_tmp/server.log"; echo "FAIL: the server did not grant soft levels for 2 lights"; exit 1; }
expect_served "$tmp/granted.out" "soft levels granted" 25  # all but the frames before the first buffer
# What ships (--warp auto) tests depth in a scene with soft lights: the traced depth is splatted on most frames.
python3 - "$tmp/granted/stats.jsonl" <<'PY'
import json, sys
eyes = [e for line in open(sys.argv[1]).read().splitlines() for e in json.loads(line)["eyes"]]
made = sum(e["traced_depth_rendered"] for e in eyes)
assert made >= len(eyes) // 2, f"traced depth made in {made} of {len(eyes)} eye frames"
print("--warp auto on soft lights: traced depth made in", made, "of", len(eyes), "eye frames")
PY
stop_server
server_pid=""

start_server "$server_exe" "$scene" "$tmp/server2" --soft-levels off
if run_client refused; then echo "FAIL: the client accepted one bit per light for soft lights"; exit 1; fi
grep -q "have an extent" "$tmp/refused.err" || { tail -n 5 "$tmp/refused.err"; echo "FAIL: no reason given"; exit 1; }
echo "soft levels refused by the server: the client says $(grep -o 'one bit per light[^(]*' "$tmp/refused.err" | head -n1)"
rm -rf "$tmp"
echo "PASS"
