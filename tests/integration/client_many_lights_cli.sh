#!/usr/bin/env bash
# More than 32 lights end to end: the project's default room with 45 more point lights of 0.9 m range (48 in all,
# written here as a glTF), served by dhr-server, whose lights then share light slots, and shown by dhr-xrclient
# (offscreen), which derives the same slots, offers them and shades every frame from the server's fields.
# Usage: client_many_lights_cli.sh DHR_SERVER DHR_XRCLIENT SOURCE_DIR
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/client_lib.sh" "$@"
scene="$tmp/many_lights_room.gltf"
export DHR_LOG=info

python3 - "$src/assets/scenes/default_room.gltf" "$scene" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
lights = d["extensions"]["KHR_lights_punctual"]["lights"]
roots = d["scenes"][d.get("scene", 0)]["nodes"]
for x in (-1.6, -0.8, 0.0, 0.8, 1.6):
    for y in (0.5, 1.3, 2.1):
        for z in (-1.1, 0.0, 1.1):
            lights.append({"name": "bulb %g %g %g" % (x, y, z), "type": "point", "color": [1.0, 0.85, 0.7],
                           "intensity": 0.6, "range": 0.9})
            d["nodes"].append({"name": "bulb", "translation": [x, y, z],
                               "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}})
            roots.append(len(d["nodes"]) - 1)
json.dump(d, open(sys.argv[2], "w"))
print("wrote %s: %d lights" % (sys.argv[2], len(lights)))
PY

mkdir -p "$tmp/server" "$tmp/client"
start_server "$server_exe" "$scene" "$tmp/server"
"$client_exe" --scene "$scene" --server "127.0.0.1:$port" --key-file "$key_file" --trace "$trace" \
  --offscreen "$tmp/client" --eye-size 96x72 --frames 30 --png-every 0 --connect-timeout 2 >"$tmp/client.out" \
  2>"$tmp/client.err" || { tail -n 20 "$tmp/client.err"; echo "FAIL: the client's run"; exit 1; }
grep -q "mask layout: light slots: 48 lights in" "$server_tmp/server.log" ||
  { cat "$server_tmp/server.log"; echo "FAIL: the server did not place 48 lights in light slots"; exit 1; }
grep -q "share light slots: no client shadow maps" "$tmp/client.err" ||
  { tail -n 20 "$tmp/client.err"; echo "FAIL: the client did not say it has no shadow maps"; exit 1; }
expect_served "$tmp/client.out" "48 lights in light slots" 25  # all but the frames before the first buffer
stop_server
rm -rf "$tmp"
echo "PASS"
