// Layering probe (built only by the layering test): the server's trace floor sits below its session floor
// (server/CMakeLists.txt), so code that links only dhr_server_trace cannot see session/ headers. This file must
// fail to compile with "session/visibility_service.hpp" not found.
#include "session/visibility_service.hpp"

int dhr_layering_probe_trace_forbidden() { return 0; }
