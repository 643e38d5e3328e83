// trace_bench's sequence mode (--trace): recorded head motion traced with and without reuse in one run.
//   trace_bench --trace PATH [--trace PATH]... [--scene PATH] [--frames N] [--size WxH] [--sessions K]
//               [--trace-start S] [--threads N] [--soft-levels [--truth-every N]] [--no-shared] [--no-refresh]
//               [--no-blocks] [--no-pairs]
// Every frame (90 Hz) of every session is traced for both eyes twice on one Embree tracer: exhaustively
// (trace_layout) and reusing (trace_reusing, trace/reuse/reuse_frame.hpp: whole blocks from the eye's previous
// trace; pairs from it and, with sharing on, from this frame's other eye and the other sessions' newest traces).
// --no-refresh, --no-blocks, --no-pairs switch parts of the rule off (to measure what each is worth). Session k follows trace k mod T (T traces given), started
// --trace-start + 5 s x (k div T) into it. Progress goes to stderr; the last stdout line is one JSON object:
//   rays_per_eye_frame, exhaustive_rays_per_eye_frame     primary + shadow rays per traced eye
//   trace_ms_per_eye, exhaustive_trace_ms_per_eye         wall time per traced eye (median over eyes)
//   differing_bits_frac   hard fields: pixel-light bits that differ from the exhaustive trace, over hit pixels
//                         x hard lights; soft fields: differing_levels_frac, the same over soft pairs, and
//                         levels_mean_abs_difference, mean |k reused - k exhaustive| over soft pairs (a bound on
//                         how much reuse can move visibility_error against any reference)
//   visibility_error, exhaustive_visibility_error   soft levels in a static scene: mean |k - k truth| over the
//                         surface pixels' soft lights of every camera of every --truth-every'th frame (default
//                         30; 0: none), against a converged truth (sequence_truth.hpp)
// and the shadow rays, reused pairs and refreshed pixels beside them, per session too. docs/performance.md, "Reuse".
#pragma once

namespace dhr::bench {

// True when argv asks for the sequence mode (has --trace).
bool wants_trace_sequence(int argc, char** argv);

// Runs it; returns the exit code (docs/exit-codes.md).
int run_trace_sequence(int argc, char** argv);

}  // namespace dhr::bench
