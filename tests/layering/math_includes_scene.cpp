// Layering probe (built only by the layering test): dhr_math sits below dhr_scene, so code that links only
// dhr_math cannot see the scene library's headers. This file must fail to compile with "scene/scene.hpp"
// not found; if it compiles, a wrong-way include would too.
#include "scene/scene.hpp"

int dhr_layering_probe_forbidden() { return 0; }
