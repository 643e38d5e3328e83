// The one OpenXR result check. Records the expression and the source location; errors carry
// the XrResult's name. Setup code uses DHR_XR_CHECK (throws dhr::xr::XrError); per-frame code
// uses DHR_XR_TRY, which logs and returns the failing XrResult to the caller.
#pragma once
#include <openxr/openxr.h>

#include <source_location>
#include <stdexcept>
#include <string>

namespace dhr::xr {

// "XR_ERROR_SESSION_LOST" etc.; "XR_UNKNOWN_RESULT_<n>" for values this header does not know.
std::string result_name(XrResult result);

class XrError : public std::runtime_error {
 public:
  XrError(XrResult result, const char* expression, std::source_location where);
  XrResult result() const { return result_; }

 private:
  XrResult result_;
};

[[noreturn]] void throw_xr_error(XrResult result, const char* expression,
                                 std::source_location where = std::source_location::current());
void log_xr_error(XrResult result, const char* expression,
                  std::source_location where = std::source_location::current());

}  // namespace dhr::xr

#define DHR_XR_CHECK(expr)                                                    \
  do {                                                                        \
    const XrResult dhr_xr_result_ = (expr);                                   \
    if (XR_FAILED(dhr_xr_result_)) ::dhr::xr::throw_xr_error(dhr_xr_result_, #expr); \
  } while (0)

#define DHR_XR_TRY(expr)                                                      \
  do {                                                                        \
    const XrResult dhr_xr_result_ = (expr);                                   \
    if (XR_FAILED(dhr_xr_result_)) {                                          \
      ::dhr::xr::log_xr_error(dhr_xr_result_, #expr);                         \
      return dhr_xr_result_;                                                  \
    }                                                                         \
  } while (0)
