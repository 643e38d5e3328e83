// `dhr-eval compare`: the frames a client saved as pictures (dhr-xrclient --snapshot-dir or --offscreen, with
// their views.jsonl) set beside the exact shading for the same views: visibility ray-traced exactly (Embree) and
// shaded by the client's own pipeline on the path the client took. Per saved frame it writes
//   OUT/eyes_<frame>.png     both eyes as shown, side by side
//   OUT/compare_<frame>.png  shown, exact and their difference (red: shown lit but in shadow, blue: the reverse)
// and prints one JSON line; a last line sums up. docs/evaluation.md, "Comparing saved frames".
#pragma once
#include <cstdint>
#include <string>

namespace dhr::eval {

struct CompareOptions {
  std::string scene;      // the scene the client rendered
  std::string shown_dir;  // holds views.jsonl and the PNGs it names
  std::string out_dir;    // default: shown_dir
  uint32_t threads = 0;   // Embree threads (0: all cores)
  int tolerance = 2;      // largest channel difference not counted (the forward and deferred paths differ by 2)
};

// Exit code: 0 when every frame was compared, 1 when the input could not be read or a frame failed (a line says
// why; the other frames are still compared).
int run_compare(const CompareOptions& options);

}  // namespace dhr::eval
