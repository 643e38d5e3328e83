#!/usr/bin/env bash
# Issue 5 "Done when" (c): dhr-server + dhr-xrclient over loopback under Monado's simulated headset present
# >= 300 frames, and both eyes' images are non-trivial: bright (lit) and darker (shadowed) pixels present.
# Usage: client_monado_demo.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
server_exe="$1" client_exe="$2" src="$3"
if [ ! -f "$HOME/.cache/dhr-xr/env.sh" ]; then echo "SKIP: Monado not set up (scripts/setup)"; exit 77; fi
tmp="$(mktemp -d)"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export DHR_TEST_LIB="$here"
. "$here/server_lib.sh"
scene="$src/assets/scenes/default_room.gltf"
start_server "$server_exe" "$scene" "$tmp"
"$src/runtime-config/with-monado" "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --frames 300 \
  --snapshot-dir "$tmp/png" --png-every 100 --timeout 150 >"$tmp/client.out" 2>"$tmp/client.err" || {
  tail -n 20 "$tmp/client.err"; echo "FAIL: dhr-xrclient exited with an error"; exit 1; }
summary="$(tail -n 1 "$tmp/client.out")"
echo "$summary"
python3 - "$summary" "$tmp/png" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["DHR_TEST_LIB"])
from png_read import read_png
s = json.loads(sys.argv[1])
assert s["exit"] == "clean", s["exit"]
assert s["frames"] >= 300, f"only {s['frames']} frames presented"
assert s["frames_with_visibility"] > 0, "no frame used visibility from the server"
assert s["predicted_frac"] > 0.5, s["predicted_frac"]


files = sorted(f for f in os.listdir(sys.argv[2]) if f.endswith(".png"))
for eye in ("left", "right"):
    mine = [f for f in files if f.endswith(eye + ".png")]
    assert mine, f"no {eye} snapshot"
    w, h, rows = read_png(os.path.join(sys.argv[2], mine[-1]))
    lum = [(r[i] * 2126 + r[i + 1] * 7152 + r[i + 2] * 722) // 10000 for r in rows for i in range(0, len(r), 3)]
    # Relative to the brightest surfaces: a shadow on a white wall is mid-grey, not black.
    top = sorted(lum)[len(lum) * 9 // 10]
    bright = sum(v > 0.85 * top for v in lum) / len(lum)
    dark = sum(v < 0.65 * top for v in lum) / len(lum)
    print(f"{eye}: {w}x{h}, bright {bright:.3f}, dark {dark:.3f}")
    assert top > 60 and bright > 0.05 and dark > 0.02, f"{eye} eye image is trivial"
print("PASS")
PY
# --render-scale: the eyes are rendered (and traced) at half the runtime's size, the compositor scales them up.
"$src/runtime-config/with-monado" "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --frames 60 \
  --render-scale 0.5 --timeout 150 >"$tmp/half.out" 2>"$tmp/half.err" || {
  tail -n 20 "$tmp/half.err"; echo "FAIL: dhr-xrclient --render-scale 0.5 exited with an error"; exit 1; }
python3 - "$summary" "$(tail -n 1 "$tmp/half.out")" <<'PY'
import json, sys
full, half = json.loads(sys.argv[1]), json.loads(sys.argv[2])
assert half["exit"] == "clean" and half["frames"] >= 60, half
assert half["render_scale"] == 0.5 and full["render_scale"] == 1.0
assert half["eye_size"] == [round(n / 2) for n in full["eye_size"]], (half["eye_size"], full["eye_size"])
assert half["buffer_size"][0] < full["buffer_size"][0], "the server traces the smaller eye"
assert half["frames_with_visibility"] > 0 and half["predicted_frac"] > 0.5, half
print("PASS render scale", half["eye_size"])
PY
