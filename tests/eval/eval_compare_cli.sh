#!/usr/bin/env bash
# `dhr-eval compare` on frames a real client saved: dhr-server + dhr-xrclient offscreen over loopback, the head
# standing still, PNGs at frames 0 and 30 with their views.jsonl. Frame 0 was shown before the server's first
# answer (the paper's warp shades it lit): it may only be too lit, never too dark, and its shadows are missing.
# Frame 30 used visibility traced for the same still pose: it equals the exact shading but for the few pixels the
# pose's float rounding on the wire flips. Also: the pictures' sizes, and bad input (no views file, a malformed
# line, a PNG of the wrong size, a frame whose server traced another scene) fails with one line naming the problem
# while the other frames are compared; frames saved with a debug --view are skipped with the reason.
# Usage: eval_compare_cli.sh DHR_SERVER DHR_XRCLIENT DHR_EVAL SOURCE_DIR
set -euo pipefail
server_exe="$1" client_exe="$2" eval_exe="$3" src="$4"
tmp="$(mktemp -d)"
export DHR_TEST_LIB="$src/tests/integration"
. "$DHR_TEST_LIB/server_lib.sh"
scene="$src/assets/scenes/default_room.gltf"
start_server "$server_exe" "$scene" "$tmp"
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json DHR_LOG=warn
work="$(mktemp -d)"
trap 'stop_server; rm -rf "$work"' EXIT

printf '# dhr-trace v1\nt,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n2,0,0,0,0,0,0,1\n' >"$work/still.csv"
# --warp paper: frame 0, before any visibility, is shaded lit (the paper's fallback), which compare must show as too
# lit; the shipped warp would shade it from the client's shadow maps instead.
# --net-delay 20: frame 0's pose reaches the server 20 ms later, so frame 0 is shown before any visibility of it
# can arrive (without it, a server tracing 96x72 on loopback sometimes answered within frame 0's own step).
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --trace "$work/still.csv" \
  --offscreen "$work/shown" --eye-size 96x72 --frames 31 --png-every 30 --net-delay 20 --warp paper \
  >"$work/client.out" 2>"$work/client.err" || {
  tail -n 20 "$work/client.err"; echo "FAIL: dhr-xrclient"; exit 1; }
"$eval_exe" compare --scene "$scene" --shown "$work/shown" --out "$work/pictures" --threads 1 \
  >"$work/compare.out" 2>"$work/compare.err" || { cat "$work/compare.err"; echo "FAIL: dhr-eval compare"; exit 1; }
cat "$work/compare.err"

python3 - "$work" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["DHR_TEST_LIB"])
from png_read import read_png
work = sys.argv[1]
views = [json.loads(l) for l in open(f"{work}/shown/views.jsonl")]
assert [v["frame"] for v in views] == [0, 30], views
assert views[0]["eye_size"] == [96, 72] and views[0]["render_path"] == "forward", views[0]
assert views[1]["guard_per_side"] is not None, "frame 30 was rendered in a session"
assert all(len(v["scene_hash"]) == 16 for v in views), "the Welcome's scene hash is recorded"
lines = [json.loads(l) for l in open(f"{work}/compare.out").read().splitlines()]
frames, summary = lines[:-1], lines[-1]
assert summary["summary"] and summary["compared"] == 2 and summary["failed"] == 0, summary
first, later = frames
assert not any(e["has_visibility"] for e in first["eyes"]), first
for e in first["eyes"]:
    assert e["too_lit_frac"] > 0.02, f"frame 0 shaded lit should miss the room's shadows: {e}"
    assert e["too_dark_frac"] == 0.0, f"a frame shaded lit cannot be darker than the exact shading: {e}"
for e in later["eyes"]:
    assert e["has_visibility"] and e["age"] >= 1, e
    assert e["differing_frac"] < 0.002, f"a still head's frame 30 should equal the exact shading: {e}"
    assert e["ssim"] > 0.99, e
assert later["differing_frac"] < first["differing_frac"] / 10, (first, later)
for line in frames:
    w, h, _ = read_png(line["eyes_picture"])
    assert w >= 2 * 96 * 4 and h >= 72 * 4, (line["eyes_picture"], w, h)  # both eyes, scaled up 5x
    w, h, rows = read_png(line["comparison_picture"])
    assert w >= 2 * 96 * 4 and h >= 3 * 72 * 4, (line["comparison_picture"], w, h)
# Frame 0's difference row is red (too lit) where the room's shadows are.
_, _, rows = read_png(frames[0]["comparison_picture"])
red = sum(1 for r in rows for i in range(0, len(r), 3) if (r[i], r[i + 1], r[i + 2]) == (255, 64, 48))
assert red > 100, f"only {red} red pixels in frame 0's difference"
print("PASS compare:", [round(f["differing_frac"], 5) for f in frames])
PY

# Bad input: each fails with one line on stderr and a non-zero exit code (2 for an unusable input file, 1 for a
# frame that cannot be compared: docs/exit-codes.md).
expect_failure() {  # name, text the error must contain, then the arguments
  local name="$1" want="$2"; shift 2
  if "$eval_exe" compare --scene "$scene" "$@" >"$work/$name.out" 2>"$work/$name.err"; then
    echo "FAIL: $name: exit 0"; exit 1
  fi
  grep -q -- "$want" "$work/$name.err" || { cat "$work/$name.err"; echo "FAIL: $name: no '$want'"; exit 1; }
}
mkdir -p "$work/empty"
expect_failure no_views "views.jsonl: cannot open" --shown "$work/empty"
mkdir -p "$work/bad"
cp "$work/shown/views.jsonl" "$work/bad/views.jsonl"
printf '{"frame": 1, "eye_size": [96, 72]}\n' >>"$work/bad/views.jsonl"
expect_failure bad_line "views.jsonl:3: frame: no \"render_path\"" --shown "$work/bad"
# A PNG of another size: that frame fails, the other is still compared.
cp "$work/shown/views.jsonl" "$work/shown"/*.png "$work/bad/"
cp "$work/pictures/eyes_000000.png" "$work/bad/frame_000030_left.png"
expect_failure wrong_size "but the frame's eyes are 96x72" --shown "$work/bad" --out "$work/bad_out"
python3 - "$work/wrong_size.out" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert "differing_frac" in lines[0] and "error" in lines[1] and lines[2]["failed"] == 1, lines
PY
# A frame the server traced from another scene (its Welcome's hash differs from --scene's): refused.
mkdir -p "$work/other"
cp "$work/shown"/*.png "$work/other/"
python3 - "$work/shown/views.jsonl" "$work/other/views.jsonl" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
lines[1]["scene_hash"] = "0123456789abcdef"
open(sys.argv[2], "w").write("".join(json.dumps(l) + "\n" for l in lines))
PY
expect_failure other_scene "frame 30: the server traced another scene (hash 0123456789abcdef" --shown "$work/other" \
  --out "$work/other_out"
# Frames saved with a debug view are skipped with the reason, not compared with the shaded exact image.
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --trace "$work/still.csv" \
  --offscreen "$work/light" --eye-size 96x72 --frames 31 --png-every 30 --view light:0 >/dev/null 2>"$work/light.err" || {
  tail -n 20 "$work/light.err"; echo "FAIL: dhr-xrclient --view light:0"; exit 1; }
"$eval_exe" compare --scene "$scene" --shown "$work/light" --threads 1 >"$work/light.out" 2>/dev/null || {
  echo "FAIL: compare of debug-view frames exited with an error"; exit 1; }
python3 - "$work/light.out" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert [l.get("skipped") for l in lines[:-1]] == ["the pictures show --view light:0, not the shaded image"] * 2, lines
assert lines[-1]["compared"] == 0 and lines[-1]["skipped"] == 2, lines[-1]
PY
echo "PASS bad input"
