#!/usr/bin/env bash
# dhr-xrclient's offscreen trace playback from the command line, as a user runs it: the summary contract
# (last stdout line, one JSON object), PNGs of both eyes, per-frame JSON lines, the light-visibility debug
# view (--view light:N), --guard as both sides together, --render-path deferred, and clear errors for a bad --view
# or an odd --guard.
# Usage: client_offscreen_cli.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/client_lib.sh" "$@"
scene="$src/assets/scenes/default_room.gltf"
start_server "$server_exe" "$scene" "$tmp"
export DHR_LOG=warn

run_client() {  # name, then extra arguments
  local name="$1"; shift
  mkdir -p "$tmp/$name"
  "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --trace "$trace" --offscreen "$tmp/$name" \
    --eye-size 96x72 --frames 45 --png-every 44 --stats-jsonl "$tmp/$name/stats.jsonl" "$@" \
    >"$tmp/$name.out" 2>"$tmp/$name.err"
}

run_client shaded --net-delay 20 || { tail -n 20 "$tmp/shaded.err"; echo "FAIL: shaded run"; exit 1; }
run_client light --view light:0 --guard 8x6 || { tail -n 20 "$tmp/light.err"; echo "FAIL: --view light:0 run"; exit 1; }
run_client edges --warp edges || { tail -n 20 "$tmp/edges.err"; echo "FAIL: --warp edges run"; exit 1; }
# --render-path deferred: the same warp on the G-buffer, warp and shading passes (what auto takes on a discrete GPU).
run_client deferred --warp edges --render-path deferred ||
  { tail -n 20 "$tmp/deferred.err"; echo "FAIL: --render-path deferred run"; exit 1; }

python3 - "$tmp" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["DHR_TEST_LIB"])
from png_read import read_png
tmp = sys.argv[1]
for name in ("shaded", "light"):
    summary = json.loads(open(f"{tmp}/{name}.out").read().strip().splitlines()[-1])
    for key in ("frames", "fps", "response_ms_median", "bits_per_frame", "predicted_frac", "unknown_frac"):
        assert key in summary, f"{name}: summary lacks {key}: {summary}"
    assert summary["exit"] == "clean" and summary["frames"] == 45, summary
    assert summary["frames_with_visibility"] > 0, summary
    # What ships (--warp auto) in this hard-lit room: no depth test, so no traced depth.
    assert not any(e["traced_depth_rendered"] for line in open(f"{tmp}/{name}/stats.jsonl").read().splitlines()
                   for e in json.loads(line)["eyes"]), name
    lines = open(f"{tmp}/{name}/stats.jsonl").read().splitlines()
    assert len(lines) == 45, f"{name}: {len(lines)} stats lines"
    for line in lines: json.loads(line)
    pngs = sorted(f for f in os.listdir(f"{tmp}/{name}") if f.endswith(".png"))
    assert len(pngs) == 4, f"{name}: PNGs {pngs}"  # frames 0 and 44, both eyes
    # --guard counts both sides together; the default is the paper's 64x36 at 1920x1080, scaled (4x2 at 96x72).
    assert summary["guard"] == ([8, 6] if name == "light" else [4, 2]), summary["guard"]
    # --render-path auto on lavapipe: the forward pass where it applies (not the light view, a debug view).
    assert summary["render_path"] == "auto", summary
    assert summary["render_passes"] == ("deferred" if name == "light" else "forward"), summary
    print(name, summary["view"], "frames", summary["frames"], "predicted", round(summary["predicted_frac"], 3))

# --warp edges: the server's bits on the forward path, the shadow maps where the samples disagree or none is usable.
summary = json.loads(open(f"{tmp}/edges.out").read().strip().splitlines()[-1])
assert summary["exit"] == "clean" and summary["frames"] == 45 and summary["frames_with_visibility"] > 0, summary
eyes = [e for line in open(f"{tmp}/edges/stats.jsonl").read().splitlines() for e in json.loads(line)["eyes"]]
assert all(e["forward"] for e in eyes), "--warp edges left the forward path"
assert summary["render_passes"] == "forward", summary
deferred = json.loads(open(f"{tmp}/deferred.out").read().strip().splitlines()[-1])
assert deferred["exit"] == "clean" and deferred["frames_with_visibility"] > 0, deferred
assert deferred["render_path"] == "deferred" and deferred["render_passes"] == "deferred", deferred
eyes = [e for line in open(f"{tmp}/deferred/stats.jsonl").read().splitlines() for e in json.loads(line)["eyes"]]
assert not any(e["forward"] for e in eyes), "--render-path deferred took the forward pass"
assert sum(e["known"] for e in eyes) > 0 and sum(e["filled_shadow_map"] for e in eyes) > 0, eyes[-1]
print("edges: known", sum(e["known"] for e in eyes), "filled from the shadow maps", sum(e["filled_shadow_map"] for e in eyes))

# The light view of the last frame: lit (230), shadowed (26), unknown (red) or background; both lit and
# shadowed present (light 0 of the default room casts shadows into the camera's view).
w, h, rows = read_png(os.path.join(tmp, "light", sorted(f for f in os.listdir(f"{tmp}/light") if f.endswith("left.png"))[-1]))
colours = {}
for r in rows:
    for i in range(0, len(r), 3):
        colours[tuple(r[i:i + 3])] = colours.get(tuple(r[i:i + 3]), 0) + 1
lit, shadowed = colours.get((230, 230, 230), 0), colours.get((26, 26, 26), 0)
print("light view: lit", lit, "shadowed", shadowed, "of", w * h)
assert lit > w * h // 20 and shadowed > w * h // 100, colours
assert lit + shadowed + colours.get((255, 0, 0), 0) > w * h // 2, colours
PY

# Bad --view values: a usage error (exit 2) or, for a light the server does not trace, a clear one-line error.
if "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --view sideways >/dev/null 2>"$tmp/bad1.err"; then
  echo "FAIL: --view sideways accepted"; exit 1; fi
grep -q -- "--view 'sideways'" "$tmp/bad1.err" || { cat "$tmp/bad1.err"; echo "FAIL: no --view message"; exit 1; }
if run_client badlight --view light:9; then echo "FAIL: --view light:9 accepted for 3 lights"; exit 1; fi
grep -q -- "--view light:9" "$tmp/badlight.err" || { cat "$tmp/badlight.err"; echo "FAIL: no light message"; exit 1; }
# An odd guard band cannot be split evenly between the sides: a usage error, exit 2.
set +e
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --guard 7x6 >/dev/null 2>"$tmp/badguard.err"
rc=$?
set -e
[ "$rc" -eq 2 ] || { cat "$tmp/badguard.err"; echo "FAIL: --guard 7x6 exit $rc, expected 2"; exit 1; }
grep -q "even" "$tmp/badguard.err" || { cat "$tmp/badguard.err"; echo "FAIL: no even-guard message"; exit 1; }
# --edge-band above its 8 pixels: a usage error naming the option, exit 2; 0 (no band) runs.
set +e
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --edge-band 9 >/dev/null 2>"$tmp/badband.err"
rc=$?
set -e
[ "$rc" -eq 2 ] || { cat "$tmp/badband.err"; echo "FAIL: --edge-band 9 exit $rc, expected 2"; exit 1; }
grep -q -- "--edge-band" "$tmp/badband.err" || { cat "$tmp/badband.err"; echo "FAIL: no --edge-band message"; exit 1; }
run_client noband --warp edges --edge-band 0 || { tail -n 20 "$tmp/noband.err"; echo "FAIL: --edge-band 0 run"; exit 1; }
# --shadow-fill-period-ms: negative or not a number is a usage error naming the option, exit 2.
for bad in -1 nan; do
  set +e
  "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --shadow-fill-period-ms "$bad" \
    >/dev/null 2>"$tmp/badperiod.err"
  rc=$?
  set -e
  [ "$rc" -eq 2 ] || { cat "$tmp/badperiod.err"; echo "FAIL: --shadow-fill-period-ms $bad exit $rc, expected 2"; exit 1; }
  grep -q -- "--shadow-fill-period-ms" "$tmp/badperiod.err" ||
    { cat "$tmp/badperiod.err"; echo "FAIL: no --shadow-fill-period-ms message"; exit 1; }
done
# --traced-depth: raster or splat only (exit 2 naming the option); splat makes the depth test's traced depth from
# the previous frame (from the second frame with a buffer on), without a raster pass.
set +e
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --traced-depth mesh >/dev/null \
  2>"$tmp/baddepth.err"
rc=$?
set -e
[ "$rc" -eq 2 ] || { cat "$tmp/baddepth.err"; echo "FAIL: --traced-depth mesh exit $rc, expected 2"; exit 1; }
grep -q -- "--traced-depth" "$tmp/baddepth.err" ||
  { cat "$tmp/baddepth.err"; echo "FAIL: no --traced-depth message"; exit 1; }
run_client splat --warp edges-depth --traced-depth splat --depth-scale 1 ||
  { tail -n 20 "$tmp/splat.err"; echo "FAIL: --traced-depth splat run"; exit 1; }
python3 - "$tmp/splat/stats.jsonl" <<'PY'
import json, sys
eyes = [e for line in open(sys.argv[1]).read().splitlines() for e in json.loads(line)["eyes"]]
made = [e for e in eyes if e["traced_depth_rendered"]]
assert made and all(e["traced_depth_ms"] >= 0 for e in made), eyes[-1]
assert sum(e["known"] for e in eyes) > 0, eyes[-1]
print("splat: traced depth made in", len(made), "of", len(eyes), "eye frames")
PY
echo PASS
