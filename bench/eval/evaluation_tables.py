#!/usr/bin/env python3
"""Fills the generated tables of docs/evaluation.md from docs/eval/<run>/results.json and report.md.

Usage: bench/eval/evaluation_tables.py [repo root]   (run_all.sh calls it last)

Each table sits between <!-- GENERATED:name --> and <!-- /GENERATED:name --> and is replaced whole; a block
whose runs are missing is left as it is (with a note on stderr). A table right after a
``dhr-eval run --out docs/eval/RUN ...`` line is replaced by RUN's report.md table. Nothing else changes.
"""
import json
import os
import re
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EVAL = os.path.join(ROOT, "docs", "eval")
PAGE = os.path.join(ROOT, "docs", "evaluation.md")


def load(run):
    path = os.path.join(EVAL, run, "results.json")
    if not os.path.exists(path):
        raise FileNotFoundError(path)
    with open(path) as f:
        return {(r["method"], int(round(r["rtt_ms"]))): r for r in json.load(f)}


def label(run):
    return run.replace("headline_", "").replace("_", " ")


def pct(value, digits=4):
    return f"{100.0 * value:.{digits}f} %"


def full_local():
    lines = ["| run | RTT ms | paper+pred bit error | local | full | paper+pred SSIM | local | full | full / paper+pred |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for run in ("living_room_user1", "living_room_user2", "default_room_user1", "default_room_user2"):
        r = load(run)
        for rtt in (0, 25, 50, 100, 200):
            p, l, f = r[("paper+pred", rtt)], r[("local", rtt)], r[("full", rtt)]
            ratio = f"{f['bit_error'] / p['bit_error']:.3f}" if p["bit_error"] > 0 else "-"
            lines.append(f"| {label(run)} | {rtt} | {pct(p['bit_error'])} | {pct(l['bit_error'])} | {pct(f['bit_error'])} | "
                         f"{p['ssim']:.5f} | {l['ssim']:.5f} | {f['ssim']:.5f} | {ratio} |")
    return lines


def fills():
    r = load("living_room_user1")
    lines = ["What `full` fills and what it costs, living room User1, 160x120 (shares of the display pixels; times per eye):",
             "",
             "| RTT ms | own eye gave no mask | filled: other eye | filled: previous buffer | filled: neighbours | "
             "filled: shadow maps | unfilled | disoccluded | "
             "undecided bits -> maps | confident map bit replaced an agreed one | traced FOV widened (eyes) | "
             "warp ms paper+pred | warp ms full | traced depth ms | client ms paper+pred | client ms full |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for rtt in (25, 50, 100, 200):
        p, f = r[("paper+pred", rtt)], r[("full", rtt)]
        lines.append(f"| {rtt} | {pct(f['unknown_frac'], 2)} | {pct(f['filled_other_eye_frac'], 2)} | "
                     f"{pct(f.get('filled_older_frac', 0.0), 2)} | {pct(f.get('filled_neighbour_frac', 0.0), 2)} | "
                     f"{pct(f['filled_shadow_map_frac'], 2)} | {pct(f['unfilled_frac'], 2)} | {pct(f['disoccluded_frac'], 2)} | "
                     f"{pct(f['edges_shadow_map_frac'], 2)} | {pct(f['shadow_overrides_frac'], 2)} | "
                     f"{pct(f.get('fov_widened_frac', 0.0), 1)} | {p['warp_ms']:.2f} | {f['warp_ms']:.2f} | "
                     f"{f['traced_depth_ms']:.1f} | {p['client_ms']:.1f} | {f['client_ms']:.1f} |")
    return lines


def method_table(run, columns):
    r = load(run)
    methods = []
    for (m, _rtt) in r:
        if m not in methods:
            methods.append(m)
    lines = [f"`{run}`:", "", "| method | " + " | ".join(c[0] for c in columns) + " |",
             "|---|" + "---:|" * len(columns)]
    for m in methods:
        cells = []
        for _title, key, rtt, fmt in columns:
            row = r.get((m, rtt))
            cells.append(fmt(row[key]) if row is not None and key in row else "-")
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return lines


def ablation():
    cols = [("bit error 100 ms", "bit_error", 100, pct), ("SSIM 100 ms", "ssim", 100, lambda v: f"{v:.5f}"),
            ("bit error 200 ms", "bit_error", 200, pct), ("SSIM 200 ms", "ssim", 200, lambda v: f"{v:.5f}"),
            ("own eye gave no mask 200 ms", "unknown_frac", 200, lambda v: pct(v, 2)),
            ("disoccluded 200 ms", "disoccluded_frac", 200, lambda v: pct(v, 2)),
            ("unfilled 200 ms", "unfilled_frac", 200, lambda v: pct(v, 2))]
    maps_off = cols[:4] + [("filled: previous buffer 200 ms", "filled_older_frac", 200, lambda v: pct(v, 2)),
                           ("filled: neighbours 200 ms", "filled_neighbour_frac", 200, lambda v: pct(v, 2)),
                           ("unfilled 200 ms", "unfilled_frac", 200, lambda v: pct(v, 2))]
    return (method_table("living_room_user1_ablation", cols) + [""] +
            method_table("living_room_user1_ablation_server_first", cols) + [""] +
            method_table("living_room_user1_fills_without_maps", maps_off) + [""])


def adaptive_fov():
    out = []
    for run in ("living_room_user1_adaptive_fov", "living_room_user2_adaptive_fov"):
        cols = []
        for rtt in (50, 100, 200):
            cols += [(f"bit error {rtt} ms", "bit_error", rtt, pct),
                     (f"own eye gave no mask {rtt} ms", "unknown_frac", rtt, lambda v: pct(v, 2))]
        cols += [("eyes widened 200 ms", "fov_widened_frac", 200, lambda v: pct(v, 1)),
                 ("traced / display FOV area 200 ms", "fov_area_ratio", 200, lambda v: f"{v:.3f}"),
                 ("bytes/frame 200 ms", "bytes_per_frame", 200, lambda v: f"{v:.0f}")]
        out += method_table(run, cols) + [""]
    return out


def headline():
    lines = ["| scene, trace | RTT ms | paper+pred bit error | local | full | full / paper+pred | paper+pred SSIM | local | full |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for scene in ("living_room", "default_room"):
        for user in (1, 2, 3):
            run = f"headline_{scene}_user{user}"
            r = load(run)
            for rtt in (50, 100, 200):
                p, l, f = r[("paper+pred", rtt)], r[("local", rtt)], r[("full", rtt)]
                lines.append(f"| {label(run)} | {rtt} | {pct(p['bit_error'])} | {pct(l['bit_error'])} | "
                             f"{pct(f['bit_error'])} | {f['bit_error'] / p['bit_error']:.3f} | {p['ssim']:.5f} | "
                             f"{l['ssim']:.5f} | {f['ssim']:.5f} |")
    return lines


BLOCKS = {"full_local": full_local, "fills": fills, "ablation": ablation, "adaptive_fov": adaptive_fov,
          "headline": headline}


def report_tables(page):
    """Each ``dhr-eval run --out docs/eval/RUN ...`` line followed by a table gets RUN's report.md table."""
    out = []
    lines = page.split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        out.append(line)
        m = re.match(r"``dhr-eval run --out docs/eval/(\S+) ", line)
        i += 1
        if not m:
            continue
        report = os.path.join(EVAL, m.group(1), "report.md")
        if not os.path.exists(report):
            print(f"evaluation_tables.py: no {report}: its table is left as it is", file=sys.stderr)
            continue
        with open(report) as f:
            table = [l for l in f.read().split("\n") if l.startswith("|")]
        while i < len(lines) and lines[i] == "":
            out.append(lines[i])
            i += 1
        if i < len(lines) and lines[i].startswith("|"):
            while i < len(lines) and lines[i].startswith("|"):
                i += 1
            out.extend(table)
    return "\n".join(out)


def main():
    with open(PAGE) as f:
        page = f.read()
    page = report_tables(page)
    for name, make in BLOCKS.items():
        pattern = re.compile(r"(<!-- GENERATED:%s -->\n)(.*?)(<!-- /GENERATED:%s -->)" % (name, name), re.S)
        if not pattern.search(page):
            print(f"evaluation_tables.py: no block {name} in {PAGE}", file=sys.stderr)
            continue
        try:
            body = "\n".join(make()) + "\n"
        except (FileNotFoundError, KeyError) as e:
            print(f"evaluation_tables.py: block {name} left as it is: missing {e}", file=sys.stderr)
            continue
        page = pattern.sub(lambda m: m.group(1) + body + m.group(3), page, count=1)
    with open(PAGE, "w") as f:
        f.write(page)


if __name__ == "__main__":
    main()
