// One picture per round trip from a run's snapshots (dhr-eval run --snapshot-frame F --snapshot-crop X,Y,W,H): the
// same crop of the exact image and of each method's, scaled up side by side and labelled, with each method's
// wrong bits below it (red: lit where the truth is shadowed, and so on; eval_session's wrong-bits pictures).
// For readers who would rather look than read a table.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dhr::eval {

struct CropRect {
  uint32_t x = 0, y = 0, width = 0, height = 0;
};

// "X,Y,W,H" (W, H >= 1); std::nullopt otherwise.
std::optional<CropRect> parse_crop(const std::string& text);

struct CropPicture {
  std::string out_dir;               // the run's --out (its snapshots/ holds the PNGs)
  std::vector<std::string> methods;  // method names as the snapshots are named (method_name())
  std::string rtt;                   // as in the file names ("100")
  std::string guard;                 // guard label ("64x36")
  int eye = 0;
  CropRect crop;
};

// Writes <out>/snapshots/crop_rtt<R>_guard<G>_eye<E>.png and returns its path; a one-line reason when a
// snapshot is missing or the crop does not lie inside the images.
std::optional<std::string> write_crop_picture(const CropPicture& request, std::string* out_error);

}  // namespace dhr::eval
