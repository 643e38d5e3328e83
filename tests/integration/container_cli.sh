#!/usr/bin/env bash
# Opt-in (scripts/setup --container): the dhr-server container image built by scripts/container, served to a real
# dhr-xrclient with a deployment key, twice: `podman run` on the host network, and deploy/kubernetes/dhr-server.yaml
# started by `podman kube play` (the key a Secret mounted as a file, readiness from /metrics). The manifests are
# also parsed offline by kubectl (deploy/kubernetes/*.yaml; no cluster here). Skips (77) without podman, mmdebstrap
# or root. Usage: container_cli.sh DHR_XRCLIENT SOURCE_DIR BUILD_DIR
set -euo pipefail
client_exe="$1" src="$2" build="$3"
for tool in podman mmdebstrap catatonit runc; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool is not installed (opt-in: scripts/setup --container)"; exit 77; }
done
[ "$(id -u)" = 0 ] || { echo "SKIP: the container test runs rootful podman (needs root)"; exit 77; }
export CONTAINERS_CONF="${CONTAINERS_CONF:-$src/deploy/container/containers.conf}"
podman info >/dev/null 2>&1 || { echo "SKIP: podman cannot run here: $(podman info 2>&1 | tail -n 1)"; exit 77; }

start=$(date +%s)
tmp="$(mktemp -d)"
name="dhr-server-test-$$"
kube_yaml="$tmp/kube.yaml"
cleanup() {
  podman rm -f "$name" >/dev/null 2>&1 || true
  [ -f "$kube_yaml" ] && podman kube down "$kube_yaml" >/dev/null 2>&1 || true
  podman secret rm "$name-key" >/dev/null 2>&1 || true
  podman volume rm "$name-key" >/dev/null 2>&1 || true
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

# The image, from this build (set-up and build are the caller's).
DHR_BUILD_DIR="$build" DHR_CONTAINER_SKIP_SETUP=1 "$src/scripts/container" >"$tmp/container.json" 2>"$tmp/container.err" \
  || { cat "$tmp/container.err"; fail "scripts/container"; }
tail -n 1 "$tmp/container.json"

free_port() {  # a port free for both UDP and TCP on loopback
  python3 -c 'import socket
while True:
    t = socket.socket(); t.bind(("127.0.0.1", 0)); p = t.getsockname()[1]
    u = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try: u.bind(("127.0.0.1", p)); break
    except OSError: t.close()
print(p)'
}
"$build/server/dhr-server" --gen-key "$tmp/dhr.key" 2>/dev/null || fail "dhr-server --gen-key"
scene="$src/assets/scenes/default_room.gltf"
trace="$src/assets/traces/synthetic_6dof.csv"
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json DHR_LOG=warn

wait_ready() {  # metrics port: readiness as the manifest's probe sees it
  for _ in $(seq 1 150); do
    curl -fs -o /dev/null "http://127.0.0.1:$1/metrics" && return 0
    sleep 0.2
  done
  return 1
}
run_client() {  # label, port
  "$client_exe" --scene "$scene" --server "127.0.0.1:$2" --key-file "$tmp/dhr.key" --trace "$trace" \
    --offscreen "$tmp/$1" --eye-size 96x72 --frames 45 --png-every 0 >"$tmp/$1.out" 2>"$tmp/$1.err" \
    || { tail -n 20 "$tmp/$1.err"; fail "$1: dhr-xrclient exited $?"; }
  python3 - "$tmp/$1.out" "$1" <<'PY'
import json, sys
summary = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
assert summary["exit"] == "clean" and summary["frames"] == 45, summary
assert summary["frames_with_visibility"] > 0, f"{sys.argv[2]}: no visibility from the container: {summary}"
print(f"{sys.argv[2]}: 45 frames, {summary['frames_with_visibility']} with the server's visibility")
PY
}

# 1. podman run on the host network, the key bind-mounted (mode 0600 kept).
port=$(free_port); metrics=$(free_port)
podman run -d --name "$name" --network=host -v "$tmp/dhr.key:/run/dhr/dhr.key:ro" localhost/dhr-server:latest \
  --port "$port" --bind 127.0.0.1 --metrics-port "$metrics" --key-file /run/dhr/dhr.key --scene /scenes/default_room.gltf \
  --threads 1 >/dev/null || fail "podman run"
wait_ready "$metrics" || { podman logs "$name" 2>&1 | tail; fail "podman run: /metrics never answered"; }
run_client run "$port"
podman stop -t 10 "$name" >/dev/null
podman logs "$name" >"$tmp/run.log" 2>&1
grep -q '"frames_traced"' "$tmp/run.log" || { tail "$tmp/run.log"; fail "podman run: no statistics line after SIGTERM"; }
podman rm "$name" >/dev/null

# 2. podman kube play: a Secret holding the key (base64 `data`, as `kubectl create secret generic` writes it) and the
# manifest as shipped, renamed and on free ports.
port=$(free_port); metrics=$(free_port)
python3 - "$src/deploy/kubernetes/dhr-server.yaml" "$kube_yaml" "$name" "$port" "$metrics" "$tmp/dhr.key" <<'PY'
import base64, sys, yaml
manifest, out, name, port, metrics, key = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
deployment = yaml.safe_load(open(manifest))
spec = deployment["spec"]["template"]["spec"]
deployment["metadata"]["name"] = name
spec["volumes"][0]["secret"]["secretName"] = name + "-key"
server = spec["containers"][0]
args = server["args"]
args[args.index("--port") + 1] = str(port)
args[args.index("--metrics-port") + 1] = str(metrics)
args[args.index("--threads") + 1] = "1"
# No --bind: inside the pod's network namespace the server listens on every address, as hostPort forwards to the pod.
for p in server["ports"]:
    p["containerPort"] = p["hostPort"] = port if p["protocol"] == "UDP" else metrics
for probe in ("readinessProbe", "livenessProbe"):
    server[probe]["httpGet"]["port"] = metrics
secret = {"apiVersion": "v1", "kind": "Secret", "metadata": {"name": name + "-key"}, "type": "Opaque",
          "data": {"dhr.key": base64.b64encode(open(key, "rb").read()).decode()}}
open(out, "w").write(yaml.safe_dump_all([secret, deployment]))
PY
podman kube play "$kube_yaml" >"$tmp/play.out" 2>&1 || { cat "$tmp/play.out"; fail "podman kube play"; }
pod_container="$name-pod-0-server"  # podman names a Deployment's pod <name>-pod-0
wait_ready "$metrics" || { podman logs "$pod_container" 2>&1 | tail; fail "kube play: /metrics never answered"; }
run_client kube "$port"
podman kube down "$kube_yaml" >/dev/null 2>&1 || fail "podman kube down"

# 3. What kubectl checks offline: each manifest parses as Kubernetes objects.
if command -v kubectl >/dev/null; then
  for f in "$src"/deploy/kubernetes/*.yaml; do
    kubectl label --local -f "$f" dhr-checked=offline --dry-run=client -o name >/dev/null 2>"$tmp/kubectl.err" \
      || { cat "$tmp/kubectl.err"; fail "kubectl does not parse $f"; }
  done
  echo "kubectl parsed deploy/kubernetes/*.yaml offline"
fi
echo "PASS: container test in $(( $(date +%s) - start )) s"
