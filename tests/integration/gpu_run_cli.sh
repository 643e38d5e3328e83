#!/usr/bin/env bash
# The prepared GPU run, rehearsed here on lavapipe: scripts/gpu-bundle (no data, uncompressed) then scripts/gpu-run
# --quick --driver lavapipe in an emptied environment, every program started through the bundle's own loader and
# libraries. Every step must pass and write its JSON. Usage: gpu_run_cli.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src="$1" build="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
[ -f /usr/share/vulkan/icd.d/lvp_icd.json ] || { echo "SKIP: no lavapipe ICD"; exit 77; }
DHR_BUILD_DIR="$build" DHR_GPU_BUNDLE_SKIP_BUILD=1 "$src/scripts/gpu-bundle" --out "$tmp/bundle" --no-data --no-compress \
  >"$tmp/bundle.json" 2>"$tmp/bundle.err" || { cat "$tmp/bundle.err"; echo "FAIL: gpu-bundle"; exit 1; }
env -i PATH=/usr/bin:/bin HOME="$tmp" TMPDIR="$tmp" "$src/scripts/gpu-run" --bundle "$tmp/bundle/dhr-gpu" --out "$tmp/results" \
  --quick --driver lavapipe --no-links >"$tmp/run.out" 2>"$tmp/run.err" || { cat "$tmp/run.err" "$tmp/results/log.txt"; echo "FAIL: gpu-run"; exit 1; }
python3 - "$tmp/results" <<'PY'
import json, os, sys
out = sys.argv[1]
summary = json.load(open(f"{out}/summary.json"))
assert summary["all_passed"], summary
assert [s["step"] for s in summary["steps"]] == ["vulkan_tracer", "vulkan_tests", "trace_bench"] + ["trace_many_lights"] * 3 + [
    "client_bench"] + ["client_bench_many_lights"] * 4 + ["dhr_eval", "end_to_end"], summary
assert "llvmpipe" in summary["vulkan_device"], summary
tracer = json.load(open(f"{out}/vulkan_tracer.json"))
assert tracer["tests"] > 0 and tracer["failures"] == 0, "VulkanTracer tests did not all pass"
assert any(json.loads(l).get("backend") == "vulkan" for l in open(f"{out}/trace_bench.jsonl")), "no Vulkan trace_bench record"
json.loads(open(f"{out}/client_bench.jsonl").read().strip().splitlines()[-1])
assert json.load(open(f"{out}/eval_results.json")), "empty dhr-eval results"
e2e = json.load(open(f"{out}/e2e.json"))
assert e2e["client"]["exit"] == "clean" and e2e["client"]["frames_with_visibility"] > 0, e2e
assert e2e["server"] is not None, "no statistics line from dhr-server"
assert len(os.listdir(out)) <= 8, os.listdir(out)  # what the device tool brings back
print(f"PASS: {len(summary['steps'])} steps, {tracer['tests']} VulkanTracer tests")
PY
