#include "picture_canvas.hpp"

// stb_truetype's implementation, private to this file (static).
#define STB_TRUETYPE_IMPLEMENTATION
#define STBTT_STATIC
#include <stb/stb_truetype.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>

namespace dhr::eval {

Canvas::Canvas(uint32_t width, uint32_t height, Rgb background) {
  image_.width = width;
  image_.height = height;
  image_.rgb.resize(size_t{width} * height * 3);
  fill(0, 0, static_cast<int>(width), static_cast<int>(height), background);
}

void Canvas::fill(int x, int y, int width, int height, Rgb colour) {
  const int x0 = std::max(x, 0), y0 = std::max(y, 0);
  const int x1 = std::min(x + width, static_cast<int>(image_.width));
  const int y1 = std::min(y + height, static_cast<int>(image_.height));
  for (int py = y0; py < y1; ++py) {
    for (int px = x0; px < x1; ++px) {
      uint8_t* p = &image_.rgb[(size_t(py) * image_.width + size_t(px)) * 3];
      p[0] = colour.r;
      p[1] = colour.g;
      p[2] = colour.b;
    }
  }
}

void Canvas::blit(const RgbImage& image, int x, int y, uint32_t scale) {
  const int s = static_cast<int>(std::max(scale, 1u));
  for (uint32_t sy = 0; sy < image.height; ++sy) {
    for (uint32_t sx = 0; sx < image.width; ++sx) {
      const uint8_t* p = &image.rgb[(size_t(sy) * image.width + sx) * 3];
      fill(x + static_cast<int>(sx) * s, y + static_cast<int>(sy) * s, s, s, Rgb{p[0], p[1], p[2]});
    }
  }
}

void Canvas::blend(int x, int y, Rgb colour, uint8_t coverage) {
  if (x < 0 || y < 0 || x >= static_cast<int>(image_.width) || y >= static_cast<int>(image_.height)) return;
  uint8_t* p = &image_.rgb[(size_t(y) * image_.width + size_t(x)) * 3];
  const auto mix = [coverage](uint8_t under, uint8_t over) {
    return static_cast<uint8_t>((under * (255 - coverage) + over * coverage + 127) / 255);
  };
  p[0] = mix(p[0], colour.r);
  p[1] = mix(p[1], colour.g);
  p[2] = mix(p[2], colour.b);
}

std::string default_font_path() {
  const char* env = std::getenv("DHR_FONT");
  return env != nullptr && *env != '\0' ? env : "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

namespace {

// How far the pen moves past text[i]: its advance plus the kerning with the next character.
float advance(const stbtt_fontinfo& info, const std::string& text, size_t i, float scale) {
  const int c = static_cast<unsigned char>(text[i]);
  int width = 0, lsb = 0;
  stbtt_GetCodepointHMetrics(&info, c, &width, &lsb);
  float out = static_cast<float>(width) * scale;
  if (i + 1 < text.size()) {
    out += static_cast<float>(stbtt_GetCodepointKernAdvance(&info, c, static_cast<unsigned char>(text[i + 1]))) * scale;
  }
  return out;
}

}  // namespace

struct TextFace::Impl {
  std::vector<unsigned char> data;
  stbtt_fontinfo info{};
  int ascent = 0, descent = 0;
};

TextFace::TextFace() : impl_(std::make_unique<Impl>()) {}
TextFace::~TextFace() = default;

std::unique_ptr<TextFace> TextFace::load(const std::string& path, std::string* out_error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (out_error != nullptr) *out_error = path + ": cannot open the font";
    return nullptr;
  }
  std::unique_ptr<TextFace> face(new TextFace());
  face->impl_->data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  const unsigned char* data = face->impl_->data.data();
  const int offset = face->impl_->data.size() >= 12 ? stbtt_GetFontOffsetForIndex(data, 0) : -1;
  if (offset < 0 || stbtt_InitFont(&face->impl_->info, data, offset) == 0) {
    if (out_error != nullptr) *out_error = path + ": not a TrueType font";
    return nullptr;
  }
  int gap = 0;
  stbtt_GetFontVMetrics(&face->impl_->info, &face->impl_->ascent, &face->impl_->descent, &gap);
  return face;
}

int TextFace::width(const std::string& text, float pixels) const {
  const float scale = stbtt_ScaleForPixelHeight(&impl_->info, pixels);
  float pen = 0.0f;
  for (size_t i = 0; i < text.size(); ++i) pen += advance(impl_->info, text, i, scale);
  return static_cast<int>(pen + 0.5f);
}

int TextFace::draw(Canvas& canvas, int x, int y, const std::string& text, float pixels, Rgb colour) const {
  const stbtt_fontinfo& info = impl_->info;
  const float scale = stbtt_ScaleForPixelHeight(&info, pixels);
  const int baseline = y + static_cast<int>(static_cast<float>(impl_->ascent) * scale + 0.5f);
  float pen = static_cast<float>(x);
  std::vector<unsigned char> glyph;
  for (size_t i = 0; i < text.size(); ++i) {
    const int c = static_cast<unsigned char>(text[i]);
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    stbtt_GetCodepointBitmapBox(&info, c, scale, scale, &x0, &y0, &x1, &y1);
    const int w = x1 - x0, h = y1 - y0;
    if (w > 0 && h > 0) {
      glyph.assign(size_t(w) * size_t(h), 0);
      stbtt_MakeCodepointBitmap(&info, glyph.data(), w, h, w, scale, scale, c);
      const int gx = static_cast<int>(pen + 0.5f) + x0;
      for (int py = 0; py < h; ++py) {
        for (int px = 0; px < w; ++px) canvas.blend(gx + px, baseline + y0 + py, colour, glyph[size_t(py) * w + px]);
      }
    }
    pen += advance(info, text, i, scale);
  }
  return static_cast<int>(pen + 0.5f) - x;
}

}  // namespace dhr::eval
