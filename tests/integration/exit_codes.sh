#!/usr/bin/env bash
# Every executable against the one exit-code table (docs/exit-codes.md, shared/cli/include/cli/exit_codes.hpp):
# --help is 0, an unknown option 2, an unusable input file 2; the client's bad address and unreadable key file 2,
# a server that traces another scene 5 (and the same --lights on both ends 0), a wrong key 4; a bad --node-script 2.
# Usage: exit_codes.sh BUILD_DIR SOURCE_DIR   (executables that were not built are skipped, named)
set -uo pipefail
build="$1" src="$2"
tmp="$(mktemp -d)"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
. "$here/server_lib.sh"
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json DHR_LOG=warn
scene="$src/assets/scenes/default_room.gltf"
trace="$src/assets/traces/synthetic_6dof.csv"
bad_scene="$tmp/bad.gltf"
echo '{"asset": {"version": "2.0"}, "meshes": 7}' >"$bad_scene"
missing="$tmp/does-not-exist.gltf"
failures=0

expect() {  # expected-code, name, command...
  local want="$1" name="$2"; shift 2
  "$@" >"$tmp/out" 2>"$tmp/err" </dev/null
  local got=$?
  if [ "$got" != "$want" ]; then
    echo "FAIL: $name: exit $got, want $want"; tail -n 5 "$tmp/err"; failures=$((failures + 1))
  else
    echo "ok: $name: exit $got"
  fi
}
exe() { [ -x "$build/$1" ] && echo "$build/$1"; }

for e in server/dhr-server xrclient/dhr-xrclient bench/eval/dhr-eval tools/dhr-trace-convert tools/dhr-protocol-layout \
         bench/codec_bench bench/trace_bench bench/skip_bench bench/client_bench bench/secure_bench \
         bench/motion_bench bench/soft_bench tests/fuzz/dhr_fuzz_seeds; do
  path="$(exe "$e")" || { echo "skip: $e not built"; continue; }
  expect 0 "$e --help" "$path" --help
  expect 2 "$e --no-such-option" "$path" --no-such-option
done

# An unusable scene file (missing, malformed) is bad input everywhere.
if server="$(exe server/dhr-server)"; then
  for s in "$missing" "$bad_scene"; do expect 2 "dhr-server --check $(basename "$s")" "$server" --check --scene "$s"; done
  expect 2 "dhr-server --threads 100000" "$server" --check --scene "$scene" --threads 100000
  expect 2 "dhr-server unreadable key file" "$server" --scene "$scene" --port 0 --key-file "$missing"
  expect 2 "dhr-server --bind not-an-address" "$server" --scene "$scene" --port 0 --insecure --bind not-an-address
fi
client="$(exe xrclient/dhr-xrclient)" || client=""
if [ -n "$client" ]; then
  play=(--trace "$trace" --offscreen "$tmp/frames" --eye-size 64x48 --frames 10 --png-every 0 --connect-timeout 5)
  expect 2 "dhr-xrclient bad scene" "$client" --scene "$bad_scene" --server 127.0.0.1:9 "${play[@]}"
  expect 2 "dhr-xrclient --server without a port" "$client" --scene "$scene" --server nohostport "${play[@]}"
  printf '# dhr-trace v1\nt,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n0.1,nan,0,0,0,0,0,1\n' >"$tmp/nan.csv"
  expect 2 "dhr-xrclient trace with a NaN position" "$client" --scene "$scene" --server 127.0.0.1:9 --trace "$tmp/nan.csv" \
    --offscreen "$tmp/frames" --png-every 0
  expect 2 "dhr-xrclient missing trace" "$client" --scene "$scene" --server 127.0.0.1:9 --trace "$missing" \
    --offscreen "$tmp/frames" --png-every 0
  expect 2 "dhr-xrclient unreadable key file" "$client" --scene "$scene" --server 127.0.0.1:9 --key-file "$missing" "${play[@]}"
  expect 2 "dhr-xrclient --start-at offscreen" "$client" --scene "$scene" --server 127.0.0.1:9 --start-at bookmark "${play[@]}"
  # The default room moves nothing: any node in a --node-script is refused, naming the line.
  printf '# moves\n{"t": 0.5, "node": 0, "translation": [0, 1, 0]}\n' >"$tmp/nodes.jsonl"
  expect 2 "dhr-xrclient --node-script naming a node that cannot move" "$client" --scene "$scene" \
    --server 127.0.0.1:9 --node-script "$tmp/nodes.jsonl" "${play[@]}"
  grep -q "nodes.jsonl:2: node 0 is not a node the scene lets move" "$tmp/err" \
    || { echo "FAIL: --node-script error names the file and line"; cat "$tmp/err"; failures=$((failures + 1)); }
  expect 2 "dhr-xrclient missing --node-script" "$client" --scene "$scene" --server 127.0.0.1:9 \
    --node-script "$missing" "${play[@]}"
fi
# The project's scripts that take options: --help 0, an unknown option 2 (nothing is built or installed then).
for s in scripts/container scripts/gpu-bundle scripts/gpu-run scripts/setup; do
  expect 0 "$s --help" "$src/$s" --help
  expect 2 "$s unknown option" "$src/$s" --no-such-option
done
expect 2 "scripts/gpu-run missing bundle" "$src/scripts/gpu-run" --bundle "$missing" --out "$tmp/gpu"
expect 2 "dhr-install-key unreadable key" "$src/deploy/container/dhr-install-key" "$missing" "$tmp/key"
if ev="$(exe bench/eval/dhr-eval)"; then
  expect 2 "dhr-eval run bad scene" "$ev" run --scene "$bad_scene" --trace "$trace" --out "$tmp/eval" --no-progress
  expect 2 "dhr-eval run missing trace" "$ev" run --scene "$scene" --trace "$missing" --out "$tmp/eval" --no-progress
  expect 2 "dhr-eval run --threads 100000" "$ev" run --scene "$scene" --trace "$trace" --threads 100000 --out "$tmp/eval"
  mkdir -p "$tmp/shown"
  expect 2 "dhr-eval compare without views.jsonl" "$ev" compare --scene "$scene" --shown "$tmp/shown"
fi
if tc="$(exe tools/dhr-trace-convert)"; then expect 2 "dhr-trace-convert missing input" "$tc" "$missing" "$tmp/t.csv"; fi
if b="$(exe bench/codec_bench)"; then expect 2 "codec_bench bad scene" "$b" --scene "$bad_scene"; fi
if b="$(exe bench/trace_bench)"; then
  expect 2 "trace_bench bad scene" "$b" --scene "$bad_scene" --quick --no-vulkan
  for v in -1 70000 abc ""; do
    expect 2 "trace_bench --soft-history '$v'" "$b" --trace "$trace" --soft-levels --soft-history "$v" --frames 1
  done
  for v in -1 7.5 nan abc ""; do
    expect 2 "trace_bench --soft-hysteresis '$v'" "$b" --trace "$trace" --soft-levels --soft-hysteresis "$v" --frames 1
  done
fi
if b="$(exe bench/codec_bench)"; then
  for v in yes "" 1; do expect 2 "codec_bench --reuse '$v'" "$b" --trace "$trace" --reuse "$v" --frames 1; done
  for v in 0 101 abc; do
    expect 2 "codec_bench --coding-repeats '$v'" "$b" --trace "$trace" --coding-repeats "$v" --frames 1
  done
  expect 2 "codec_bench sequence, bad scene" "$b" --scene "$bad_scene" --trace "$trace" --frames 1
  expect 2 "codec_bench sequence, missing trace" "$b" --trace "$missing" --frames 1
  # Sequence-mode options without --trace are named, not silently dropped.
  expect 0 "codec_bench --reuse without --trace" "$b" --scene synthetic --size 64x48 --repeat 1 --reuse on
  grep -q "warning: --reuse: only the sequence mode" "$tmp/err" || {
    echo "FAIL: codec_bench does not name --reuse without --trace"; cat "$tmp/err"; failures=$((failures + 1)); }
fi
if b="$(exe bench/skip_bench)"; then expect 2 "skip_bench bad scene" "$b" --scene "$bad_scene"; fi
if b="$(exe bench/client_bench)"; then
  expect 2 "client_bench bad scene" "$b" --scene "$bad_scene" --quick
  for v in 0 8 5000 nan ten; do expect 2 "client_bench --shadow-size '$v'" "$b" --shadow-size "$v" --quick; done
fi

# The scene checked on both ends: a server started with --lights traces another scene than the file's.
if [ -n "$client" ] && server="$(exe server/dhr-server)"; then
  lights="point:0,2.5,0:1,1,1:20"
  start_server "$server" "$scene" "$tmp" --lights "$lights"
  expect 5 "dhr-xrclient against a server with another scene (its --lights)" \
    "$client" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" "${play[@]}"
  grep -q "another scene" "$tmp/err" || { echo "FAIL: the scene mismatch is not named on stderr"; cat "$tmp/err"; failures=$((failures + 1)); }
  expect 0 "dhr-xrclient with the server's --lights" \
    "$client" --scene "$scene" --lights "$lights" --server "127.0.0.1:$port" --key-file "$key_file" "${play[@]}"
  "$server" --gen-key "$tmp/other.key" 2>/dev/null
  expect 4 "dhr-xrclient with another key" \
    "$client" --scene "$scene" --lights "$lights" --server "127.0.0.1:$port" --key-file "$tmp/other.key" "${play[@]}"
fi
rm -rf "$tmp/frames" "$tmp/eval" "$tmp/shown"
[ "$failures" = 0 ] || { echo "FAIL: $failures exit code(s) differ from the table"; exit 1; }
echo "PASS: every exit code follows the table"
