#!/usr/bin/env python3
"""The human-readable summary scripts/demo prints on stderr: what ran, how fast, how right, where the pictures are.

Reads the client's JSON summary (docs/client.md) and, when there, the lines `dhr-eval compare` printed
(docs/evaluation.md, "Comparing saved frames"). Prints nothing on stdout.

Usage: demo_summary.py --client FILE [--compare FILE] --out DIR [--server ADDR] [--frames-dir DIR] [--scene FILE]
                       [--start NAME] [--video FILE]
"""
import argparse
import json
import os
import sys


def last_json_line(path):
    """The last line of the file that parses as a JSON object, or None."""
    try:
        lines = open(path, encoding="utf-8", errors="replace").read().splitlines()
    except OSError:
        return None
    for line in reversed(lines):
        try:
            value = json.loads(line)
        except ValueError:
            continue
        if isinstance(value, dict):
            return value
    return None


def json_lines(path):
    out = []
    try:
        for line in open(path, encoding="utf-8", errors="replace"):
            try:
                value = json.loads(line)
            except ValueError:
                continue
            if isinstance(value, dict):
                out.append(value)
    except OSError:
        pass
    return out


def pct(fraction):
    if fraction is None:
        return "n/a"
    value = 100.0 * fraction
    return f"{value:.3f} %" if 0 < value < 0.1 else f"{value:.2f} %"


# The headset's rate the demo aims for (Monado's null compositor paces at 90 Hz).
TARGET_FPS = 85.0


def below_target(s):
    """Why the run stayed below TARGET_FPS, from the client's own per-eye GPU time, or None."""
    fps = s.get("fps", 0.0)
    if s.get("mode") != "openxr" or fps >= TARGET_FPS:
        return None
    eye_ms = s.get("eye_gpu_ms_median") or 0.0
    update_ms = s.get("shadow_update_ms_median") or 0.0
    cores = os.cpu_count() or 1
    because = (f"the client's passes took {eye_ms:.1f} ms per eye (median) on the Vulkan device it used"
               if eye_ms > 0 else "the client's frames took longer than the headset's period")
    if update_ms > 0:
        because += f", and re-rendering the shadow maps that moving things made stale {update_ms:.1f} ms per frame"
    return (f"Rate:     {fps:.1f} fps, below the headset's {TARGET_FPS:g}: {because}, two eyes a frame, with "
            f"dhr-server and Monado on the same {cores} cores; a CPU rasterizer (lavapipe) is bound by the scene's "
            f"geometry here (measured rates per scene and size: docs/client.md, \"Measured\"; a GPU headset renders "
            f"this at its full rate)")


def describe_run(s, server):
    lines = []
    size = "x".join(str(n) for n in s.get("eye_size", []))
    if s.get("mode") == "openxr":
        scale = s.get("render_scale", 1.0)
        where = f"OpenXR (Monado's simulated headset), eyes rendered at {size}"
        if scale != 1.0:
            where += f" (render scale {scale:g})"
    else:
        where = f"offscreen, {s.get('pose_source', 'a pose source')}, eyes {size}"
    lines.append(f"Headset:  {s.get('frames', 0)} frames at {s.get('fps', 0.0):.1f} fps, {where}; exit {s.get('exit')}")
    reason = below_target(s)
    if reason:
        lines.append(reason)
    if server:
        lights = s.get("lights")
        extra = f", {lights} light{'s' if lights != 1 else ''}" if lights is not None else ""
        lines.append(f"Server:   dhr-server at {server}{extra}, codec {s.get('codec', 'n/a')}, every datagram authenticated")
    frames = max(1, s.get("frames", 0))
    kbit = s.get("bits_per_frame", 0.0) / 1000.0
    mbit_s = s.get("bits_per_frame", 0.0) * s.get("fps", 0.0) / 1e6
    response = s.get("response_ms_median")
    age = s.get("age_frames_median")
    lines.append(f"Shadows:  {pct(s.get('predicted_frac'))} of surface pixels from the server's ray-traced bits "
                 f"(warped to the current pose), {pct(s.get('unknown_frac'))} unknown")
    timing = f"response {response:.1f} ms median" if response is not None else "no response measured"
    if age is not None:
        timing += f", visibility {age:g} frame{'s' if age != 1 else ''} old (median)"
    lines.append(f"          {timing}; {kbit:.1f} kbit per frame ({mbit_s:.2f} Mbit/s); "
                 f"{s.get('frames_with_visibility', 0)} of {frames} frames used server visibility")
    return lines


def frame_list(frames):
    """'3, 6, 9' for a few frames, '3 to 90 (30 frames)' for many."""
    if len(frames) <= 6:
        return ", ".join(str(f) for f in frames)
    return f"{frames[0]} to {frames[-1]} ({len(frames)} frames)"


def describe_pictures(compared, out, frames_dir):
    lines = []
    done = [c for c in compared if "differing_frac" in c]
    failed = [c for c in compared if "error" in c]
    skipped = [c for c in compared if "skipped" in c]
    if done:
        with_data = [c for c in done if all(e.get("has_visibility") for e in c["eyes"])]
        without = [c for c in done if c not in with_data]
        if with_data:
            worst = max(c["differing_frac"] for c in with_data)
            mean = sum(c["differing_frac"] for c in with_data) / len(with_data)
            frames = frame_list([c["frame"] for c in with_data])
            # Soft shadows differ by a level's rounding almost everywhere in a penumbra: SSIM says how much.
            ssims = [e["ssim"] for c in with_data for e in c["eyes"] if e.get("ssim") is not None]
            ssim = f", SSIM {sum(ssims) / len(ssims):.3f}" if ssims else ""
            lines.append(f"Accuracy: shown vs exact shading for the same pose: {pct(mean)} of pixels differ by more "
                         f"than 2/255 in a channel (mean of frames {frames}; worst {pct(worst)}{ssim})")
        for c in without:
            lines.append(f"          frame {c['frame']}, before the server's first answer: {pct(c['differing_frac'])} "
                         f"of pixels differ")
        newest = (with_data or done)[-1]
        lines.append(f"Pictures: {out}")
        lines.append(f"          {os.path.basename(newest['eyes_picture'])}  both eyes as shown (frame {newest['frame']})")
        lines.append(f"          {os.path.basename(newest['comparison_picture'])}  shown, exact and where they differ "
                     f"(red: shown lit but in shadow; blue: the reverse)")
        others = [c["frame"] for c in done if c is not newest]
        if others:
            lines.append(f"          the same for frame{'s' if len(others) > 1 else ''} {frame_list(others)}")
    for c in failed:
        lines.append(f"Pictures: frame {c['frame']} could not be compared: {c['error']}")
    for c in skipped:
        lines.append(f"Pictures: frame {c['frame']} not compared: {c['skipped']}")
    if not compared:
        lines.append(f"Pictures: none compared (see {os.path.join(out, 'compare.log')})")
    if frames_dir:
        lines.append(f"          {frames_dir}: the client's own PNGs and views.jsonl (their exact views)")
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--client", required=True, help="the client's stdout (its JSON summary is the last line)")
    parser.add_argument("--compare", help="dhr-eval compare's stdout")
    parser.add_argument("--out", required=True, help="the demo's output directory")
    parser.add_argument("--server", help="the server's address")
    parser.add_argument("--frames-dir", help="where the client saved its PNGs")
    parser.add_argument("--scene", help="the scene shown")
    parser.add_argument("--start", help="the camera bookmark the head started at")
    parser.add_argument("--video", help="the video scripts/demo made")
    args = parser.parse_args()

    summary = last_json_line(args.client)
    lines = ["", "DHR-XR demo"]
    if summary is None:
        lines.append(f"The client printed no summary (its log: {os.path.join(args.out, 'client.log')}).")
    else:
        if args.scene:
            start = f", the head starting at bookmark '{args.start}'" if args.start else ""
            lines.append(f"Scene:    {args.scene}{start}")
        lines += describe_run(summary, args.server)
    if args.compare:
        compared = [c for c in json_lines(args.compare) if "frame" in c]
        lines += describe_pictures(compared, args.out, args.frames_dir)
    if args.video:
        strips = sum(1 for f in os.listdir(args.out) if f.startswith("strip_") and f.endswith(".png"))
        lines.append(f"Video:    {args.video}  left eye as shown | exact | difference, {strips} saved frames at 15 fps")
    lines.append(f"Logs:     {args.out} (server.log, client.log, compare.log)")
    lines.append("The client's JSON summary (docs/client.md) is the last line on stdout.")
    print("\n".join("  " + l if i > 1 else l for i, l in enumerate(lines)), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
