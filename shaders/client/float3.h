// vec3 from float[3]: the structs shared with C++ (shaders/shader_interface.h) carry vectors as three floats
// so that their std430 and C++ layouts agree. GLSL only.
#ifndef DHR_FLOAT3_H
#define DHR_FLOAT3_H

vec3 v3(float a[3]) { return vec3(a[0], a[1], a[2]); }

#endif  // DHR_FLOAT3_H
