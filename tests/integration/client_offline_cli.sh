#!/usr/bin/env bash
# Offline mode (dhr-xrclient --warp full): a client whose server dies mid-run keeps presenting, shading with
# its own shadow maps, keeps sending Hello with backoff, and takes server visibility again once a server is
# back on the same port. The server runs with a 1 s session timeout so the loss is noticed quickly.
# Usage: client_offline_cli.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
server_exe="$1" client_exe="$2" src="$3"
tmp="$(mktemp -d)"
scene="$src/assets/scenes/default_room.gltf"
trace="$src/assets/traces/synthetic_6dof.csv"
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json DHR_LOG=warn
server_pid="" client_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill -KILL "$server_pid" 2>/dev/null || true
  [ -n "$client_pid" ] && kill -KILL "$client_pid" 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT

key_file="$tmp/dhr.key"
"$server_exe" --gen-key "$key_file" 2>/dev/null
serve() {  # port (0: any), log file; sets server_pid and port
  "$server_exe" --scene "$scene" --port "$1" --threads 1 --session-timeout-ms 1000 --key-file "$key_file" \
    2>"$2" >/dev/null &
  server_pid=$!
  for _ in $(seq 1 300); do
    port="$(sed -n 's/.*listening on .*:\([0-9][0-9]*\)$/\1/p' "$2" | head -n1)"
    [ -n "$port" ] && return 0
    sleep 0.1
  done
  cat "$2"; echo "FAIL: dhr-server did not listen"; exit 1
}

serve 0 "$tmp/server1.log"
mkdir -p "$tmp/out"
# 720 frames paced at 90 Hz: 8 s of presenting.
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --trace "$trace" --offscreen "$tmp/out" \
  --eye-size 64x48 --frames 720 --png-every 0 --warp full --connect-timeout 0.5 \
  --stats-jsonl "$tmp/out/stats.jsonl" >"$tmp/client.out" 2>"$tmp/client.err" &
client_pid=$!
sleep 2
kill -KILL "$server_pid"; wait "$server_pid" 2>/dev/null || true   # the server is lost, without a Bye
server_pid=""
sleep 2.5
serve "$port" "$tmp/server2.log"                                      # back, on the same port
wait "$client_pid" || { tail -n 30 "$tmp/client.err"; echo "FAIL: client exited with an error"; exit 1; }
client_pid=""

python3 - "$tmp" <<'PY'
import json, sys
tmp = sys.argv[1]
summary = json.loads(open(f"{tmp}/client.out").read().strip().splitlines()[-1])
frames = [json.loads(l) for l in open(f"{tmp}/out/stats.jsonl")]
assert summary["exit"] == "clean" and summary["frames"] == 720 and len(frames) == 720, summary
have = [all(e["has_visibility"] for e in f["eyes"]) for f in frames]
# Server visibility at first, none for a stretch (the session lost), then server visibility again.
first_lost = next(i for i in range(len(have)) if i > 0 and have[i - 1] and not have[i])
back = next(i for i in range(first_lost, len(have)) if have[i])
local = sum(1 for f in frames[first_lost:back] if sum(e["filled_shadow_map"] for e in f["eyes"]) > 0)
print("lost at frame", first_lost, "back at frame", back, "local frames", local, "summary local", summary["frames_local"],
      "restarts", summary["net"]["sessions_restarted"], "hellos backed off", summary["net"]["hellos_backed_off"])
assert sum(have[:first_lost]) > 60, "server visibility before the loss"
assert local == back - first_lost and local > 60, "every frame without the server is shaded with the shadow maps"
assert sum(have[back:]) > 60 and have[-1], "server visibility again after the restart"
assert summary["frames_local"] >= local and summary["pixels_shadow_map"] > 0, summary
assert summary["net"]["sessions_restarted"] >= 1 and summary["net"]["hellos_backed_off"] >= 1, summary["net"]
assert summary["reconnects"] == summary["net"]["sessions_restarted"], summary
# Visibility traced by the second server is for frames after the restart.
assert frames[-1]["eyes"][0]["visibility_frame"] > back, frames[-1]
PY
echo "offline mode: ok"
