// Layering probe (built only by the layering test): a file of dhr_math's layer including its own headers.
// It must compile; the sibling probe, which includes the scene library from the same layer, must not.
#include "math/projection.hpp"

int dhr_layering_probe_allowed() { return static_cast<int>(dhr::Extent{1, 1}.width); }
