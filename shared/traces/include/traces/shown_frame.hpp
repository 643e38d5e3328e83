// A frame the client showed and saved as pictures: its views (exactly as rendered), how it was rendered and
// where its PNGs are. dhr-xrclient writes one JSON line per saved frame into <dir>/views.jsonl next to the PNGs
// (--snapshot-dir, --offscreen); `dhr-eval compare` reads them back to render the exact shading for the same
// views. docs/client.md, "Pictures", documents the line.
#pragma once
#include "math/pose.hpp"
#include "math/projection.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dhr {

// The file name the client writes next to its PNGs.
inline constexpr const char* kShownFramesFile = "views.jsonl";

struct ShownEye {
  View view;                      // the view this eye was rendered with (the schedule's choice)
  std::string file;               // its PNG, a plain file name in the views file's directory
  bool has_visibility = false;    // a server buffer was used (else every surface pixel was a fallback)
  uint64_t visibility_frame = 0;  // the frame that buffer was traced for
  uint64_t age = 0;               // p: frames between it and the frame shown
  bool complete = false;          // the buffer had every row
};

struct ShownFrame {
  uint64_t frame = 0;
  Extent eye_size;                      // rendered size of each eye
  std::optional<TracedFormat> traced;   // the session's traced format (display + guard band per side)
  std::optional<uint64_t> scene_hash;   // the scene content the server traced (its Welcome's hash)
  std::string render_path;              // "forward" or "deferred"
  std::string warp;                     // "paper", "full", "edges" or "edges-depth" (dhr-xrclient --warp)
  std::string view = "shaded";          // what the pictures show (--view)
  int64_t scene_time_ns = 0;            // the scene time displayed (animations; 0 when the line has none)
  std::array<ShownEye, 2> eyes{};       // [0] left, [1] right
};

// One line of JSON (no newline). Doubles are written so that they read back to the same bits.
std::string shown_frame_json(const ShownFrame& frame);

// Parses one line; std::nullopt with a one-line reason for malformed JSON, missing or mistyped fields,
// unusable views (validate_view), sizes outside 1..kMaxImageDimension, render paths or warps it does not know, scene hashes that are not 1-16 hex digits, and file names
// that are not plain names.
std::optional<ShownFrame> parse_shown_frame(std::string_view line, std::string* out_error);

// Every non-empty line of a views file; errors name the file and line.
std::optional<std::vector<ShownFrame>> read_shown_frames(const std::string& path, std::string* out_error);

}  // namespace dhr
