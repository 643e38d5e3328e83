// Layering probe (built only by the layering test): code on the server's trace floor sees its own headers.
#include "trace/visibility_tracer.hpp"

int dhr_layering_probe_trace_allowed() { return 0; }
