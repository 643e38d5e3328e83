// The pictures of `dhr-eval compare`: what the client showed next to the exact shading for the same views, and
// where they differ. Pixels differ when a channel differs by more than a tolerance; a differing pixel is "too lit"
// when the shown luma is at least the exact one (a shadow the client missed) and "too dark" otherwise (a shadow
// that is not there).
#pragma once
#include "image/png_reader.hpp"
#include "picture_canvas.hpp"

#include <array>
#include <cstdint>
#include <string>

namespace dhr::eval {

struct EyeDifference {
  uint64_t pixels = 0;
  uint64_t too_lit = 0;
  uint64_t too_dark = 0;
  RgbImage picture;  // the exact image dimmed to grey, too-lit pixels red, too-dark pixels blue

  uint64_t differing() const { return too_lit + too_dark; }
};

inline constexpr Rgb kTooLitColour{255, 64, 48};
inline constexpr Rgb kTooDarkColour{64, 150, 255};

// shown and exact must have the same size. tolerance: the largest channel difference (0..255) that is not
// counted (the client's forward and deferred paths differ by up to 2).
EyeDifference difference(const RgbImage& shown, const RgbImage& exact, int tolerance);

// Whole-number factor that makes an eye at least ~400 pixels wide (1..8).
uint32_t picture_scale(uint32_t eye_width);

// Both eyes side by side with a caption above. face may be null (no text).
RgbImage eyes_picture(const std::array<RgbImage, 2>& eyes, const TextFace* face, const std::string& caption);

struct ComparisonText {
  std::string title;
  std::string shown;       // above the shown row
  std::string exact;       // above the exact row
  std::string difference;  // above the difference row
};

// Three rows of both eyes: shown, exact, difference (with a colour legend below). face may be null.
RgbImage comparison_picture(const std::array<RgbImage, 2>& shown, const std::array<RgbImage, 2>& exact,
                            const std::array<EyeDifference, 2>& difference, const TextFace* face,
                            const ComparisonText& text);

// One eye in a row: shown | exact | difference, each labelled, with a caption above (a video frame: scripts/demo
// makes its video of these). face may be null.
RgbImage strip_picture(const RgbImage& shown, const RgbImage& exact, const EyeDifference& difference, const TextFace* face,
                       const std::string& caption);

}  // namespace dhr::eval
