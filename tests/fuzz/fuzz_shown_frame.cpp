// Fuzz target: parse_shown_frame on arbitrary text (a line of a client's views.jsonl, read by dhr-eval compare).
// Properties: no crash or sanitizer report; a rejection always says why; an accepted line has usable views and
// plain file names, and writes back to a line that parses to the same frame.
#include "fuzz_support.hpp"
#include "traces/shown_frame.hpp"

#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const std::optional<dhr::ShownFrame> frame = dhr::parse_shown_frame(text, &error);
  if (!frame) {
    DHR_FUZZ_CHECK_MSG(!error.empty(), "a rejection without a reason");
    return 0;
  }
  for (const dhr::ShownEye& eye : frame->eyes) {
    DHR_FUZZ_CHECK(!dhr::validate_view(eye.view).has_value());
    DHR_FUZZ_CHECK(!eye.file.empty() && eye.file.find('/') == std::string::npos && eye.file[0] != '.');
  }
  const std::optional<dhr::ShownFrame> again = dhr::parse_shown_frame(dhr::shown_frame_json(*frame), &error);
  DHR_FUZZ_CHECK_MSG(again.has_value(), "a written frame does not parse back");
  DHR_FUZZ_CHECK(again->frame == frame->frame && again->eye_size == frame->eye_size);
  DHR_FUZZ_CHECK(again->traced == frame->traced && again->render_path == frame->render_path);
  DHR_FUZZ_CHECK(again->scene_hash == frame->scene_hash);
  for (size_t e = 0; e < 2; ++e) {
    DHR_FUZZ_CHECK(again->eyes[e].view.pose.position == frame->eyes[e].view.pose.position);
    DHR_FUZZ_CHECK(again->eyes[e].view.pose.orientation == frame->eyes[e].view.pose.orientation);
    DHR_FUZZ_CHECK(again->eyes[e].file == frame->eyes[e].file && again->eyes[e].age == frame->eyes[e].age);
  }
  return 0;
}
