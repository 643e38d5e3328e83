# Sourced, with its arguments, by the integration scripts that serve with dhr-server and show with dhr-xrclient
# (Usage: SCRIPT DHR_SERVER DHR_XRCLIENT SOURCE_DIR): sets server_exe, client_exe, src, a temporary directory tmp and
# the shipped trace, makes lavapipe the Vulkan driver, and sources server_lib.sh (start_server, stop_server).
server_exe="$1" client_exe="$2" src="$3"
tmp="$(mktemp -d)"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export DHR_TEST_LIB="$here"
. "$here/server_lib.sh"
trace="$src/assets/traces/synthetic_6dof.csv"
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json

# expect_served OUT LABEL MIN: the client's summary (the last stdout line of OUT, one JSON object) says a clean exit
# and at least MIN frames shaded from the server's visibility; prints "LABEL: N of M frames from the server".
expect_served() {
  python3 - "$1" "$2" "$3" <<'PY'
import json, sys
s = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
assert s["exit"] == "clean", s
assert s["frames_with_visibility"] >= int(sys.argv[3]), s
print("%s: %d of %d frames from the server" % (sys.argv[2], s["frames_with_visibility"], s["frames"]))
PY
}
