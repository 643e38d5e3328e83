#!/usr/bin/env bash
# Regenerates every run behind docs/evaluation.md (results, plots, per-run report.md under docs/eval/).
# Usage: bench/eval/run_all.sh [build dir]   (run from anywhere; needs ../shared/data for the living room
# and the recorded traces; the default-room runs need nothing outside the repository.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
eval_exe="$build/bench/eval/dhr-eval"
data="$root/../shared/data"
export VK_DRIVER_FILES="${VK_DRIVER_FILES:-/usr/share/vulkan/icd.d/lvp_icd.json}" DHR_LOG="${DHR_LOG:-warn}"
cd "$root"

living="../shared/data/scenes/living_room.glb"
default="assets/scenes/default_room.gltf"
user1="../shared/data/traces/6dof/gul2020_hololens/raw/User1.csv"
user2="../shared/data/traces/6dof/gul2020_hololens/raw/User2.csv"
user3="../shared/data/traces/6dof/gul2020_hololens/raw/User3.csv"
# 2 s of trace per run (plus 0.26 s warm-up; the connection phase before it costs no rendering) keeps the
# whole set under an hour on 2 CPU cores (lavapipe).
common=(--trace-start 2 --eye-size 160x120 --rtt-ms 0,25,50,100,200 --method stale,paper,paper+pred,local,full)
# The headline: 320x240 per eye, both scenes, three users, 1 s of trace each.
headline=(--trace-start 2 --frames 90 --eye-size 320x240 --rtt-ms 50,100,200 --method paper+pred,local,full)

one() {  # name, then dhr-eval run arguments; DHR_EVAL_ONLY="a b" runs only those names
  local name="$1"; shift
  if [ -n "${DHR_EVAL_ONLY:-}" ] && [[ " $DHR_EVAL_ONLY " != *" $name "* ]]; then return 0; fi
  "$eval_exe" run --out "docs/eval/$name" "$@" --no-progress
  "$eval_exe" report "docs/eval/$name"
}

if [ ! -d "$data" ]; then
  echo "run_all.sh: $data not found: only the default room with the synthetic trace" >&2
  one default_room_synthetic --scene "$default" --trace assets/traces/synthetic_6dof.csv --frames 180 "${common[@]}"
  exit 0
fi
one living_room_user1 --scene "$living" --trace "$user1" --frames 180 "${common[@]}"
one living_room_user2 --scene "$living" --trace "$user2" --frames 180 "${common[@]}"
one default_room_user1 --scene "$default" --trace "$user1" --frames 180 "${common[@]}"
one default_room_user2 --scene "$default" --trace "$user2" --frames 180 "${common[@]}"
one living_room_user1_guard --scene "$living" --trace "$user1" --trace-start 2 --frames 90 --eye-size 160x120 \
  --rtt-ms 50,100 --method paper,paper+pred --guard 0,64x36,128x72
one living_room_user1_xmax --scene "$living" --trace "$user1" --trace-start 2 --frames 90 --eye-size 160x120 \
  --rtt-ms 100 --method paper --x-max 0,2,4,6,all
one living_room_user1_server --scene "$living" --trace "$user1" --trace-start 2 --frames 90 --eye-size 160x120 \
  --rtt-ms 0,50,100 --method paper,paper+pred --server-ms 10
one living_room_user1_ablation --scene "$living" --trace "$user1" --trace-start 2 --frames 90 --eye-size 160x120 \
  --rtt-ms 100,200 --method paper+pred,local,full,full-no-bilinear,full-no-depth,full-no-other-eye,full-no-shadow-fill,full-no-shadow-edges,full-no-shadow-first,full-no-older,full-no-neighbour,full-no-pred,full-no-adaptive-fov
# The same with the server's bits first (shadow-first off), where the other ingredients decide more pixels.
one living_room_user1_ablation_server_first --scene "$living" --trace "$user1" --trace-start 2 --frames 90 \
  --eye-size 160x120 --rtt-ms 100,200 --method full-no-shadow-first,full-no-shadow-first-no-bilinear,full-no-depth-no-shadow-first,full-no-other-eye-no-shadow-first,full-no-shadow-fill-no-shadow-first,full-no-shadow-edges-no-shadow-first,full-no-older-no-shadow-first,full-no-neighbour-no-shadow-first
# Without the shadow maps (a client without them, or lights without a map): what the buffers' own fills do.
maps_off="full-no-shadow-fill-no-shadow-edges-no-shadow-first"
one living_room_user1_fills_without_maps --scene "$living" --trace "$user1" --trace-start 2 --frames 90 \
  --eye-size 160x120 --rtt-ms 100,200 --method "$maps_off,$maps_off-no-older,$maps_off-no-neighbour,$maps_off-no-older-no-neighbour,$maps_off-no-other-eye-no-older-no-neighbour"
# The server's adaptive FOV with and without the client's fills (without them, what no buffer covers is lit).
afov=(--trace-start 2 --frames 90 --eye-size 160x120 --rtt-ms 50,100,200 --method full-no-other-eye-no-shadow-fill-no-older-no-neighbour,full-no-other-eye-no-shadow-fill-no-older-no-neighbour-no-adaptive-fov,full,full-no-adaptive-fov)
one living_room_user1_adaptive_fov --scene "$living" --trace "$user1" "${afov[@]}"
one living_room_user2_adaptive_fov --scene "$living" --trace "$user2" "${afov[@]}"
for user in 1 2 3; do
  trace_var="user$user"
  one "headline_living_room_user$user" --scene "$living" --trace "${!trace_var}" "${headline[@]}"
  one "headline_default_room_user$user" --scene "$default" --trace "${!trace_var}" "${headline[@]}"
done
# Side-by-side pictures: exact, paper and full at 100 ms (and local), one frame of the living room, User1.
one living_room_user1_pictures --scene "$living" --trace "$user1" --trace-start 2 --frames 46 --eye-size 320x240 \
  --rtt-ms 100 --method paper,paper+pred,local,full --snapshot-frame 45
# What ships against the headset alone at 100 ms: one crop of the table's shadows (docs/evaluation.md).
one living_room_user1_default_pictures --scene "$living" --trace "$user1" --trace-start 2 --frames 46 \
  --eye-size 320x240 --rtt-ms 100 --method default,local,paper+pred --snapshot-frame 45 --snapshot-crop 185,128,80,60
python3 bench/eval/evaluation_tables.py  # fills docs/evaluation.md's tables from the results
