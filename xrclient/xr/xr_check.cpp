#include "xr/xr_check.hpp"

#include <openxr/openxr_reflection.h>

#include <cstdio>

#include "log/log.hpp"

namespace dhr::xr {

std::string result_name(XrResult result) {
  // A table from the registry's reflection header: xrResultToString needs a live instance,
  // and the errors that matter most (no runtime) happen before there is one.
  switch (result) {
#define DHR_XR_RESULT_CASE(name, value) \
  case name:                            \
    return #name;
    XR_LIST_ENUM_XrResult(DHR_XR_RESULT_CASE)
#undef DHR_XR_RESULT_CASE
    default:
      break;
  }
  return "XR_UNKNOWN_RESULT_" + std::to_string(static_cast<int>(result));
}

namespace {

std::string describe(XrResult result, const char* expression, const std::source_location& where) {
  char line[64];
  std::snprintf(line, sizeof line, ":%u", static_cast<unsigned>(where.line()));
  return result_name(result) + " from " + expression + " at " + where.file_name() + line;
}

}  // namespace

XrError::XrError(XrResult result, const char* expression, std::source_location where)
    : std::runtime_error(describe(result, expression, where)), result_(result) {}

void throw_xr_error(XrResult result, const char* expression, std::source_location where) {
  throw XrError(result, expression, where);
}

void log_xr_error(XrResult result, const char* expression, std::source_location where) {
  dhr::log::error("%s", describe(result, expression, where).c_str());
}

}  // namespace dhr::xr
