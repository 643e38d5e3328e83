// An RGB canvas for pictures people look at (dhr-eval compare): filled rectangles, images scaled up by whole
// factors (nearest neighbour, so every rendered pixel stays visible), and text in a TrueType font
// (stb_truetype with Debian's DejaVu Sans; without the font the pictures carry no text).
#pragma once
#include "image/png_reader.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dhr::eval {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

class Canvas {
 public:
  Canvas(uint32_t width, uint32_t height, Rgb background);
  // Clipped to the canvas.
  void fill(int x, int y, int width, int height, Rgb colour);
  void blit(const RgbImage& image, int x, int y, uint32_t scale);
  // Mixes `colour` into one pixel with coverage 0..255 (clipped).
  void blend(int x, int y, Rgb colour, uint8_t coverage);
  const RgbImage& image() const { return image_; }

 private:
  RgbImage image_;
};

// The default font file (fonts-dejavu-core); DHR_FONT overrides it.
std::string default_font_path();

class TextFace {
 public:
  // nullptr with a one-line reason when the file cannot be read or is not a TrueType font.
  static std::unique_ptr<TextFace> load(const std::string& path, std::string* out_error);
  ~TextFace();
  TextFace(const TextFace&) = delete;
  TextFace& operator=(const TextFace&) = delete;

  // Draws ASCII text with its top-left corner at (x, y), `pixels` tall (ascent to descent); returns its width.
  int draw(Canvas& canvas, int x, int y, const std::string& text, float pixels, Rgb colour) const;
  int width(const std::string& text, float pixels) const;

 private:
  TextFace();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dhr::eval
