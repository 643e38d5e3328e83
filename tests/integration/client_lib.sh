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
