#!/usr/bin/env bash
# The Wireshark dissector (tools/wireshark/dhr.lua) under tshark on traffic captured from a real loopback run:
# an unauthenticated session (every message type in the clear), an authenticated one (sealed and tagged
# datagrams) and a handful of malformed datagrams sent to the server. Every message type and its fields
# decode; sealed bodies show as ciphertext and tag; each malformed datagram is flagged, and no other is.
# Needs root (capturing on lo) and tshark; skipped (exit 77) without them.
# Usage: dissector_cli.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
server_exe="$1" client_exe="$2" src="$3"
[ "$(id -u)" = 0 ] || { echo "SKIP: capturing on lo needs root"; exit 77; }
command -v tshark >/dev/null || { echo "SKIP: tshark is not installed (scripts/setup installs it)"; exit 77; }
tmp="$(mktemp -d)"
scene="$src/assets/scenes/default_room.gltf"
trace="$src/assets/traces/synthetic_6dof.csv"
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json DHR_LOG=warn
cap_pid="" server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill -KILL "$server_pid" 2>/dev/null || true
  [ -n "$cap_pid" ] && kill -KILL "$cap_pid" 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT

tshark -i lo -f udp -w "$tmp/cap.pcapng" -q 2>"$tmp/tshark.err" &
cap_pid=$!
for _ in $(seq 1 100); do grep -q "Capturing on" "$tmp/tshark.err" 2>/dev/null && break; sleep 0.1; done
grep -q "Capturing on" "$tmp/tshark.err" || { cat "$tmp/tshark.err"; echo "SKIP: tshark cannot capture on lo here"; exit 77; }

serve() {  # extra server arguments...; sets server_pid and port
  "$server_exe" --scene "$scene" --port 0 --bind 127.0.0.1 --threads 1 "$@" 2>"$tmp/server.log" >/dev/null &
  server_pid=$!
  port=""
  for _ in $(seq 1 300); do
    port="$(sed -n 's/.*listening on .*:\([0-9][0-9]*\)$/\1/p' "$tmp/server.log" | head -n1)"
    [ -n "$port" ] && return 0
    sleep 0.1
  done
  cat "$tmp/server.log"; echo "FAIL: dhr-server did not listen"; exit 1
}
stop_server() { kill -INT "$server_pid"; wait "$server_pid" || true; server_pid=""; }
play() {  # frames, extra client arguments...: a session that got visibility (up to 3 sessions: a loaded machine's
  # server may trace nothing within one short session)
  local frames="$1" attempt; shift
  for attempt in 1 2 3; do
    "$client_exe" --scene "$scene" --server "127.0.0.1:$port" --trace "$trace" --offscreen "$tmp/out" \
      --eye-size 64x48 --frames "$frames" --png-every 0 "$@" >"$tmp/client.out" 2>"$tmp/client.err" \
      || { tail -n 20 "$tmp/client.err"; echo "FAIL: dhr-xrclient"; exit 1; }
    python3 -c 'import json,sys; sys.exit(0 if json.loads(open(sys.argv[1]).read().splitlines()[-1]).get("responses", 0) > 0 else 1)' \
      "$tmp/client.out" && return 0
    echo "session $attempt of $frames frames got no visibility; again"
  done
  echo "FAIL: three sessions got no visibility"; exit 1
}

# 1. In the clear: every message type, and the malformed datagrams. Only the two servers' ports are read back:
# other tests may send on lo meanwhile.
serve --insecure
port1="$port"
play 40
python3 - "$port" <<'PY'
import socket, struct, sys
port = int(sys.argv[1])
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
def header(kind, flags=0, version=7, token=0, seq=0):  # version: kProtocolVersion
    return b"DHRX" + struct.pack("<BBHQI", version, kind, flags, token, seq)
bad = [
    b"DHRX\x06\x01",                                              # shorter than the header
    header(9) + b"\x00" * 8,                                      # unknown type
    header(6, flags=4, token=5) + b"\x00",                        # unknown flags
    header(6, token=5) + b"\xc8",                                 # Bye with an unknown reason
    header(1) + b"\x00" * 21 + b"\x09" + b"ab",                   # Hello whose scene id overruns
    header(4, token=5) + b"\x00" * 18 + struct.pack("<H", 500) + b"\x00" * 64,  # shard payload size wrong
    header(1, flags=1) + b"\x00" * 10,                            # sealed without room for a tag
]
for b in bad:
    s.sendto(b, ("127.0.0.1", port))
# A well-formed NodeTransform (type 7; the server drops it: no such session): node 1 from 1.5 s on.
s.sendto(header(7, token=5) + struct.pack("<Iq3d4f3f", 1, 1500000000, 0.25, -1.5, 2.0, 0, 0.6, 0, 0.8, 1, 2, 0.5),
         ("127.0.0.1", port))
print(len(bad))
PY
sleep 0.3
stop_server
# 2. Authenticated: tagged handshake, sealed session datagrams.
"$server_exe" --gen-key "$tmp/dhr.key" 2>/dev/null
serve --key-file "$tmp/dhr.key"
port2="$port"
# 60 frames: once, with the whole suite running on 2 cores, 20 left no sealed datagram with its ciphertext.
play 60 --key-file "$tmp/dhr.key"
stop_server
sleep 0.5
kill -INT "$cap_pid"; wait "$cap_pid" 2>/dev/null || true; cap_pid=""

tshark -r "$tmp/cap.pcapng" -X lua_script:"$src/tools/wireshark/dhr.lua" \
  -Y "dhr && (udp.port == $port1 || udp.port == $port2)" -T fields -E separator=/t \
  -E occurrence=f -e dhr.type -e dhr.flags -e dhr.eye_width -e dhr.buffer_width -e dhr.guard_x -e dhr.frame \
  -e dhr.shard_count -e dhr.payload_size -e dhr.send_time_ns -e dhr.reason -e dhr.ciphertext -e dhr.handshake_tag \
  -e dhr.view.position -e _ws.expert.message -e udp.length -e dhr.scene_time_ns -e dhr.node -e dhr.node.rotation \
  >"$tmp/fields.tsv" 2>"$tmp/tshark_read.err" \
  || { cat "$tmp/tshark_read.err"; echo "FAIL: tshark could not read the capture with the dissector"; exit 1; }
if grep -v "Running as user" "$tmp/tshark_read.err" | grep -q .; then
  cat "$tmp/tshark_read.err"; echo "FAIL: the dissector reported errors"; exit 1
fi

python3 - "$tmp/fields.tsv" <<'PY'
import sys
rows = [line.rstrip("\n").split("\t") for line in open(sys.argv[1]) if line.strip()]
names = ["type", "flags", "eye_width", "buffer_width", "guard_x", "frame", "shard_count", "payload_size",
         "send_time", "reason", "ciphertext", "hs_tag", "position", "expert", "udp_length", "scene_time", "node",
         "rotation"]
recs = [dict(zip(names, r + [""] * (len(names) - len(r)))) for r in rows]
malformed = [r for r in recs if r["expert"] != "" and not r["expert"].startswith("version ")]
plain = [r for r in recs if r["flags"] in ("0x0000", "0") and r not in malformed]
by_type = {}
for r in plain:
    by_type.setdefault(r["type"], []).append(r)
print("datagrams:", len(recs), "plain:", len(plain), "malformed:", len(malformed),
      "types in the clear:", sorted(by_type))
for t in ("1", "2", "3", "4", "5", "6", "7"):
    assert t in by_type, f"message type {t} not decoded in the clear"
assert all(r["eye_width"] == "64" for r in by_type["1"]), by_type["1"][:2]
assert all(int(r["buffer_width"]) > 64 and r["guard_x"] != "" for r in by_type["2"]), by_type["2"][:2]
assert all(r["frame"] != "" and r["position"] != "" and r["scene_time"] != "" for r in by_type["3"]), by_type["3"][:2]
assert all(int(r["shard_count"]) >= 1 and int(r["payload_size"]) >= 1 and int(r["scene_time"]) >= 0
           for r in by_type["4"]), by_type["4"][:2]
assert all(r["send_time"] != "" for r in by_type["5"]), by_type["5"][:2]
assert all(r["reason"] != "" for r in by_type["6"]), by_type["6"][:2]
assert all(r["node"] == "1" and r["scene_time"] == "1500000000" and r["rotation"].startswith("0.000000, 0.600000")
           for r in by_type["7"]), by_type["7"][:2]
sealed = [r for r in recs if r["flags"] == "0x0001" and r not in malformed]
tagged = [r for r in recs if r["flags"] == "0x0002"]
assert sealed, "no sealed session datagram captured"
assert all(r["ciphertext"] != "" for r in sealed), "a sealed datagram without its ciphertext: " + str(
    [r for r in sealed if r["ciphertext"] == ""][:2])
assert {r["type"] for r in sealed} >= {"3", "4", "5"}, sorted({r["type"] for r in sealed})
assert tagged and all(r["hs_tag"] != "" for r in tagged), "no tagged handshake"
assert {r["type"] for r in tagged} >= {"1", "2"}, sorted({r["type"] for r in tagged})
assert len(malformed) == 7, f"{len(malformed)} flagged malformed, 7 were sent: " + "; ".join(r["expert"] for r in malformed)
print("dissector: ok")
PY
