#!/usr/bin/env bash
# Patches an extracted Monado 25.0.0 source tree (argument 1) for DHR-XR's headless build.
# Each edit checks that it applied, so a changed upstream fails loudly instead of silently.
set -euo pipefail
src="$1"
python3 - "$src" <<'PY'
import sys, pathlib
src = pathlib.Path(sys.argv[1])

def edit(rel, old, new):
    p = src / rel
    text = p.read_text()
    if text.count(old) != 1:
        sys.exit(f"monado.patch.sh: expected exactly one '{old.strip()}' in {rel}")
    p.write_text(text.replace(old, new))

# 1. Without the main compositor (XRT_MODULE_COMPOSITOR_MAIN=OFF) the runtime still links comp_main.
edit("src/xrt/targets/openxr/CMakeLists.txt",
     "\t\t\tcomp_main\n",
     "\t\t\t$<TARGET_NAME_IF_EXISTS:comp_main>\n")

# 2. The null compositor hard-codes 20 Hz; make it 90 Hz by default and configurable with
#    XRT_COMPOSITOR_NULL_FPS (1..1000) so the headless headset runs at a headset's rate.
edit("src/xrt/compositor/null/null_compositor.c",
     'DEBUG_GET_ONCE_LOG_OPTION(log, "XRT_COMPOSITOR_LOG", U_LOGGING_INFO)\n',
     'DEBUG_GET_ONCE_LOG_OPTION(log, "XRT_COMPOSITOR_LOG", U_LOGGING_INFO)\n'
     'DEBUG_GET_ONCE_NUM_OPTION(null_fps, "XRT_COMPOSITOR_NULL_FPS", 90)\n')
edit("src/xrt/compositor/null/null_compositor.c",
     "c->settings.frame_interval_ns = U_TIME_1S_IN_NS / 20; // 20 FPS\n",
     "long dhr_fps = debug_get_num_option_null_fps();\n"
     "\tif (dhr_fps < 1 || dhr_fps > 1000) {\n"
     "\t\tdhr_fps = 90;\n"
     "\t}\n"
     "\tc->settings.frame_interval_ns = U_TIME_1S_IN_NS / dhr_fps; // DHR-XR: 90 FPS default\n")
PY
