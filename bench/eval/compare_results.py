#!/usr/bin/env python3
"""Compares two dhr-eval results.json files on every field that does not measure the host's time.

Usage: bench/eval/compare_results.py NEW.json REFERENCE.json
Prints each differing field (path: new vs reference) and exits 1 when any differs, 0 when all are equal.
Skipped, because they measure the host or GPU and vary from run to run: client_ms, server_ms, encode_ms, decode_ms,
client_gpu_timed, warp_ms, traced_depth_ms. Everything else (errors, counts, bytes, virtual-time response/horizon/connect times) is
deterministic and must be equal bit for bit.
"""
import json
import sys

HOST_TIME = {"client_ms", "server_ms", "encode_ms", "decode_ms", "client_gpu_timed", "warp_ms", "traced_depth_ms"}


def walk(new, ref, path, out):
    if isinstance(new, dict) and isinstance(ref, dict):
        for key in sorted(set(new) | set(ref)):
            if key in HOST_TIME:
                continue
            if key not in new or key not in ref:
                out.append(f"{path}.{key}: only in {'reference' if key in ref else 'new'}")
                continue
            walk(new[key], ref[key], f"{path}.{key}", out)
    elif isinstance(new, list) and isinstance(ref, list):
        if len(new) != len(ref):
            out.append(f"{path}: {len(new)} entries vs {len(ref)}")
            return
        for i, (a, b) in enumerate(zip(new, ref)):
            walk(a, b, f"{path}[{i}]", out)
    elif new != ref:
        out.append(f"{path}: {new} vs {ref}")


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    try:
        new, ref = (json.load(open(p)) for p in sys.argv[1:3])
    except (OSError, json.JSONDecodeError) as e:
        print(f"compare_results: {e}", file=sys.stderr)
        return 2
    out = []
    walk(new, ref, "", out)
    for line in out:
        print(line)
    print(f"{len(out)} differing fields" if out else "identical (every field but host times)")
    return 1 if out else 0


if __name__ == "__main__":
    sys.exit(main())
