#!/usr/bin/env bash
# scripts/demo as a new user runs it (set-up and build skipped: the suite's build is current): dhr-server +
# dhr-xrclient under Monado, then the pictures. The JSON summary is the last stdout line; stderr has the summary
# for people, naming the pictures, which exist: both eyes as shown and shown next to the exact shading. The saved
# frames (100 and 200) used server visibility and are within 2 % of the exact shading's pixels (0.05-0.19 % measured;
# a frame shaded lit differs in about 20 %: tests/eval/eval_compare_cli.sh).
# Usage: demo_script.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src="$1" build="$2"
if [ ! -f "$HOME/.cache/dhr-xr/env.sh" ]; then echo "SKIP: Monado not set up (scripts/setup)"; exit 77; fi
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
DHR_DEMO_SKIP_SETUP=1 DHR_BUILD_DIR="$build" "$src/scripts/demo" --out "$out/demo" --frames 201 \
  >"$out/stdout" 2>"$out/stderr" || { tail -n 30 "$out/stderr"; echo "FAIL: scripts/demo exited with an error"; exit 1; }
sed -n '/^DHR-XR demo/,$p' "$out/stderr"
export DHR_TEST_LIB="$src/tests/integration"
python3 - "$out" <<'PY'
import json, os, re, sys
sys.path.insert(0, os.environ["DHR_TEST_LIB"])
from png_read import read_png
out = sys.argv[1]
summary = json.loads(open(f"{out}/stdout").read().splitlines()[-1])
assert summary["exit"] == "clean" and summary["frames"] >= 201, summary
stderr = open(f"{out}/stderr").read()
human = stderr[stderr.index("DHR-XR demo"):]
for phrase in ("Headset:", "fps", "Shadows:", "Accuracy: shown vs exact shading", "Pictures: " + f"{out}/demo"):
    assert phrase in human, f"no '{phrase}' in:\n{human}"
named = re.findall(r"(eyes_\d+\.png|compare_\d+\.png)", human)
assert "eyes_000200.png" in named and "compare_000200.png" in named, named
for name in named:
    w, h, _ = read_png(f"{out}/demo/{name}")
    assert w > 400 and h > 100, (name, w, h)
lines = [json.loads(l) for l in open(f"{out}/demo/compare.jsonl")]
frames = {l["frame"]: l for l in lines if "frame" in l}
assert sorted(frames) == [100, 200], sorted(frames)  # OpenXR's frames count from 1
for n in (100, 200):
    assert all(e["has_visibility"] for e in frames[n]["eyes"]), frames[n]
    assert frames[n]["differing_frac"] < 0.02, frames[n]
print("PASS", {n: round(f["differing_frac"], 5) for n, f in frames.items()})
PY
