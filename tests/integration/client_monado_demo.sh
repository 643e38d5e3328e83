#!/usr/bin/env bash
# Issue 5 "Done when" (c): dhr-server + dhr-xrclient over loopback under Monado's simulated headset present
# >= 300 frames, and both eyes' images are non-trivial: bright (lit) and darker (shadowed) pixels present.
# Usage: client_monado_demo.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
server_exe="$1" client_exe="$2" src="$3"
if [ ! -f "$HOME/.cache/dhr-xr/env.sh" ]; then echo "SKIP: Monado not set up (scripts/setup)"; exit 0; fi
tmp="$(mktemp -d)"
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill -INT "$server_pid" 2>/dev/null && wait "$server_pid" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
scene="$src/assets/scenes/default_room.gltf"
"$server_exe" --scene "$scene" --port 0 --threads 1 2>"$tmp/server.log" >/dev/null &
server_pid=$!
port=""
for _ in $(seq 1 300); do
  port="$(sed -n 's/.*listening on .*:\([0-9][0-9]*\)$/\1/p' "$tmp/server.log" | head -n1)"
  [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$port" ] || { cat "$tmp/server.log"; echo "FAIL: dhr-server did not listen"; exit 1; }
"$src/runtime-config/with-monado" "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --frames 300 \
  --snapshot-dir "$tmp/png" --png-every 100 --timeout 150 >"$tmp/client.out" 2>"$tmp/client.err" || {
  tail -n 20 "$tmp/client.err"; echo "FAIL: dhr-xrclient exited with an error"; exit 1; }
summary="$(tail -n 1 "$tmp/client.out")"
echo "$summary"
python3 - "$summary" "$tmp/png" <<'PY'
import json, os, struct, sys, zlib
s = json.loads(sys.argv[1])
assert s["exit"] == "clean", s["exit"]
assert s["frames"] >= 300, f"only {s['frames']} frames presented"
assert s["frames_with_visibility"] > 0, "no frame used visibility from the server"
assert s["predicted_frac"] > 0.5, s["predicted_frac"]

def read_png(path):  # 8-bit RGB, non-interlaced (what dhr::write_png writes)
    data = open(path, "rb").read()
    pos, idat, w, h = 8, b"", 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR": w, h = struct.unpack(">II", body[:8])
        if kind == b"IDAT": idat += body
        pos += 12 + n
    raw, bpp, stride, rows, prev = zlib.decompress(idat), 3, w * 3, [], bytearray(w * 3)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, rows

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
