#include "compare_pictures.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace dhr::eval {

namespace {

constexpr Rgb kBackground{30, 31, 36};
constexpr Rgb kText{236, 236, 236};
constexpr Rgb kDimText{170, 172, 180};
constexpr int kMargin = 16;
constexpr int kGap = 12;
constexpr float kTitlePixels = 22.0f;
constexpr float kLabelPixels = 17.0f;

int line_height(float pixels) { return static_cast<int>(pixels * 1.35f); }

int luma(const uint8_t* p) { return (299 * p[0] + 587 * p[1] + 114 * p[2]) / 1000; }

// The widest text of a picture, so a long line widens the canvas instead of being cut.
int text_width(const TextFace* face, const std::string& text, float pixels) {
  return face != nullptr ? face->width(text, pixels) : 0;
}

void text(Canvas& canvas, const TextFace* face, int x, int y, const std::string& line, float pixels, Rgb colour) {
  if (face != nullptr && !line.empty()) face->draw(canvas, x, y, line, pixels, colour);
}

}  // namespace

EyeDifference difference(const RgbImage& shown, const RgbImage& exact, int tolerance) {
  if (shown.width != exact.width || shown.height != exact.height || shown.rgb.size() != exact.rgb.size()) {
    throw std::invalid_argument("difference: the images differ in size");
  }
  EyeDifference d;
  d.pixels = size_t{shown.width} * shown.height;
  d.picture = RgbImage{shown.width, shown.height, std::vector<uint8_t>(shown.rgb.size())};
  for (size_t i = 0; i < d.pixels; ++i) {
    const uint8_t* s = &shown.rgb[i * 3];
    const uint8_t* e = &exact.rgb[i * 3];
    uint8_t* out = &d.picture.rgb[i * 3];
    const int delta = std::max({std::abs(s[0] - e[0]), std::abs(s[1] - e[1]), std::abs(s[2] - e[2])});
    Rgb c;
    if (delta <= tolerance) {
      const auto grey = static_cast<uint8_t>(luma(e) * 2 / 5);
      c = Rgb{grey, grey, grey};
    } else if (luma(s) >= luma(e)) {
      ++d.too_lit;
      c = kTooLitColour;
    } else {
      ++d.too_dark;
      c = kTooDarkColour;
    }
    out[0] = c.r;
    out[1] = c.g;
    out[2] = c.b;
  }
  return d;
}

uint32_t picture_scale(uint32_t eye_width) {
  if (eye_width == 0) return 1;
  return std::clamp<uint32_t>((400 + eye_width - 1) / eye_width, 1, 8);
}

RgbImage eyes_picture(const std::array<RgbImage, 2>& eyes, const TextFace* face, const std::string& caption) {
  const uint32_t s = picture_scale(eyes[0].width);
  const int w = static_cast<int>(eyes[0].width * s), h = static_cast<int>(eyes[0].height * s);
  const int caption_h = face != nullptr ? line_height(kLabelPixels) : 0;
  const int width = std::max(2 * kMargin + 2 * w + kGap, 2 * kMargin + text_width(face, caption, kLabelPixels));
  Canvas canvas(static_cast<uint32_t>(width), static_cast<uint32_t>(2 * kMargin + caption_h + h), kBackground);
  text(canvas, face, kMargin, kMargin, caption, kLabelPixels, kText);
  canvas.blit(eyes[0], kMargin, kMargin + caption_h, s);
  canvas.blit(eyes[1], kMargin + w + kGap, kMargin + caption_h, s);
  return canvas.image();
}

RgbImage comparison_picture(const std::array<RgbImage, 2>& shown, const std::array<RgbImage, 2>& exact,
                            const std::array<EyeDifference, 2>& difference, const TextFace* face,
                            const ComparisonText& words) {
  const uint32_t s = picture_scale(shown[0].width);
  const int w = static_cast<int>(shown[0].width * s), h = static_cast<int>(shown[0].height * s);
  const int title_h = face != nullptr ? line_height(kTitlePixels) + kGap / 2 : 0;
  const int label_h = face != nullptr ? line_height(kLabelPixels) : 0;
  const std::string legend_lit = "red: shown lit where the exact shading is in shadow";
  const std::string legend_dark = "blue: shown in shadow where the exact shading is lit";
  int width = 2 * kMargin + 2 * w + kGap;
  for (const auto& [line, pixels] : {std::pair{words.title, kTitlePixels}, {words.shown, kLabelPixels},
                                     {words.exact, kLabelPixels}, {words.difference, kLabelPixels},
                                     {legend_lit + "     " + legend_dark, kLabelPixels}}) {
    width = std::max(width, 2 * kMargin + text_width(face, line, pixels));
  }
  const int rows_h = 3 * (label_h + h) + 2 * kGap;
  const int height = 2 * kMargin + title_h + rows_h + (face != nullptr ? kGap / 2 + label_h : 0);
  Canvas canvas(static_cast<uint32_t>(width), static_cast<uint32_t>(height), kBackground);
  int y = kMargin;
  text(canvas, face, kMargin, y, words.title, kTitlePixels, kText);
  y += title_h;
  const std::array<const std::array<RgbImage, 2>*, 2> image_rows{&shown, &exact};
  const std::array<const std::string*, 3> labels{&words.shown, &words.exact, &words.difference};
  for (int row = 0; row < 3; ++row) {
    text(canvas, face, kMargin, y, *labels[row], kLabelPixels, kDimText);
    y += label_h;
    for (int e = 0; e < 2; ++e) {
      const RgbImage& image = row < 2 ? (*image_rows[row])[e] : difference[e].picture;
      canvas.blit(image, kMargin + e * (w + kGap), y, s);
    }
    y += h + kGap;
  }
  if (face != nullptr) {
    y -= kGap / 2;
    text(canvas, face, kMargin, y, legend_lit, kLabelPixels, kTooLitColour);
    const int x = kMargin + text_width(face, legend_lit + "     ", kLabelPixels);
    text(canvas, face, x, y, legend_dark, kLabelPixels, kTooDarkColour);
  }
  return canvas.image();
}

RgbImage strip_picture(const RgbImage& shown, const RgbImage& exact, const EyeDifference& difference, const TextFace* face,
                       const std::string& caption) {
  const uint32_t s = picture_scale(shown.width);
  const int w = static_cast<int>(shown.width * s), h = static_cast<int>(shown.height * s);
  const int label_h = face != nullptr ? line_height(kLabelPixels) : 0;
  const std::array<std::string, 3> labels{"shown (warped)", "exact (ray-traced for this pose)",
                                          "difference: red too lit, blue too dark"};
  // Even sizes: video encoders want them.
  const int width = (2 * kMargin + 3 * w + 2 * kGap + 1) / 2 * 2;
  const int height = (2 * kMargin + 2 * label_h + h + 1) / 2 * 2;
  Canvas canvas(static_cast<uint32_t>(width), static_cast<uint32_t>(height), kBackground);
  text(canvas, face, kMargin, kMargin, caption, kLabelPixels, kText);
  const std::array<const RgbImage*, 3> images{&shown, &exact, &difference.picture};
  for (int i = 0; i < 3; ++i) {
    const int x = kMargin + i * (w + kGap);
    text(canvas, face, x, kMargin + label_h, labels[static_cast<size_t>(i)], kLabelPixels, kDimText);
    canvas.blit(*images[static_cast<size_t>(i)], x, kMargin + 2 * label_h, s);
  }
  return canvas.image();
}

}  // namespace dhr::eval
