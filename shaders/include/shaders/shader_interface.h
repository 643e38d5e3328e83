// Shared by GLSL and C++: descriptor binding numbers, push-constant and result structs. Both include it as
// "shaders/shader_interface.h" (C++ through the dhr_shader_headers target, GLSL through glslang's -I).
// GLSL sees plain `const uint` and structs; C++ sees the same names in namespace dhr::shader with
// fixed-width types. Keep members 4-byte scalars (no vec3) so std430/scalar and C++ layouts agree.
#ifndef DHR_SHADER_INTERFACE_H
#define DHR_SHADER_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>
#define DHR_CONST constexpr
namespace dhr::shader {
using uint = std::uint32_t;
#else
#define DHR_CONST const
#endif

// The server visibility tracer's part (bindings, VisPushConstants, VisSoftLight, VisMesh).
#include "shaders/vis_interface.h"

// ---- client (xrclient/render): G-buffer, warp and shading passes ----
// G-buffer (graphics): one combined image sampler per material (base colour, sRGB texels -> linear).
DHR_CONST uint kClientGBufferBindingBaseColor = 0;
DHR_CONST uint kClientMaterialDoubleSided = 1u;  // ClientGBufferPush::flags: no culling, back faces flip N
DHR_CONST uint kClientMaterialAlphaMask = 2u;    // discard where alpha < alpha_cutoff

DHR_CONST uint kClientMeshMoves = 4u;  // ClientGBufferPush::flags: view_proj is the model-view-projection

// Static meshes (kClientMeshMoves clear): position = view_proj * (vertex + mesh[0..2]). Moving meshes: their motion
// at the frame's scene time, composed on the CPU in double with the camera-relative translation, so the GPU never
// sees world coordinates either way.
struct ClientGBufferPush {
  float view_proj[16];  // static: projection * rotation-only view (eye at the origin); moving: that times the
                        // mesh's camera-relative model matrix (motion with origin - eye); column-major
  float mesh[9];        // static: mesh origin - eye in [0..2] (double on the CPU); moving: the normal matrix
                        // (inverse-transpose of the motion's 3x3), column-major
  uint flags;           // kClientMaterial*, kClientMeshMoves
  float base_color_r;   // linear base colour factor
  float base_color_g;
  float base_color_b;
  float base_color_a;
  float alpha_cutoff;
  uint pad0;
};

// Warp (compute, 8x8 groups): per display pixel, the light mask from the newest visibility of this eye
// (source 0), else of the other eye (source 1), else of this eye's previous buffer (source 2), else from the
// nearest pixel of source 0 on the pixel's tangent plane, else from the client's shadow maps, else all bits (lit).
DHR_CONST uint kClientWarpGroupSize = 8u;
DHR_CONST uint kClientWarpBindingDepth = 0;        // sampler2D: G-buffer depth (reversed-Z)
DHR_CONST uint kClientWarpBindingVisibility0 = 1;  // storage buffer uint[]: source 0's packed masks
DHR_CONST uint kClientWarpBindingRowValid0 = 2;    // storage buffer uint[]: bit r%32 of word r/32 = row r valid
DHR_CONST uint kClientWarpBindingMask = 3;         // r32ui image: predicted mask
DHR_CONST uint kClientWarpBindingStatus = 4;       // r32ui image: status | fill << 8 (debug, optional)
DHR_CONST uint kClientWarpBindingMotion = 5;       // rg32f image: lookup - lookup without motion (debug)
DHR_CONST uint kClientWarpBindingCounters = 6;     // storage buffer: per bucket kClientCountWords words
DHR_CONST uint kClientWarpBindingNormal = 7;       // sampler2D: G-buffer world normal
DHR_CONST uint kClientWarpBindingOldDepth0 = 8;    // sampler2D: depth of source 0's traced camera
DHR_CONST uint kClientWarpBindingVisibility1 = 9;  // source 1 (the other eye)
DHR_CONST uint kClientWarpBindingRowValid1 = 10;
DHR_CONST uint kClientWarpBindingOldDepth1 = 11;
DHR_CONST uint kClientWarpBindingParams = 12;      // storage buffer ClientWarpParams
DHR_CONST uint kClientWarpBindingShadowMap = 13;   // sampler2D: shadow map atlas (ClientShadowLight tiles)
DHR_CONST uint kClientWarpBindingShadowLights = 14;  // storage buffer ClientShadowLight[]
DHR_CONST uint kClientWarpBindingLights = 15;      // storage buffer PackedLight[] (display-eye-relative)
DHR_CONST uint kClientWarpBindingVisibility2 = 16;  // source 2 (this eye's previous buffer)
DHR_CONST uint kClientWarpBindingRowValid2 = 17;
DHR_CONST uint kClientWarpBindingOldDepth2 = 18;
DHR_CONST uint kClientWarpBindingMoved = 19;       // storage buffer ClientWarpMotion (kClientWarpMotion)
DHR_CONST uint kClientWarpBindingSoft = 20;        // r32ui image: refined soft shares (kClientWarpSoftRefine)
DHR_CONST uint kClientWarpSourceCount = 3u;

// Per-pixel outcome for source 0; every status but kKnown means this eye's buffer gave no mask.
DHR_CONST uint kClientStatusKnown = 0u;        // from source 0's buffer
DHR_CONST uint kClientStatusBackground = 1u;   // no surface (depth == 0)
DHR_CONST uint kClientStatusBehind = 2u;       // at or behind the old eye plane
DHR_CONST uint kClientStatusOutside = 3u;      // outside the old (guard-banded) buffer
DHR_CONST uint kClientStatusMissingRow = 4u;   // every looked-up row of the old buffer is missing
DHR_CONST uint kClientStatusNoData = 5u;       // no visibility buffer at all
DHR_CONST uint kClientStatusDisoccluded = 6u;  // the old buffer saw other surfaces there (depth test)
DHR_CONST uint kClientStatusCount = 7u;
// How a surface pixel without a mask from source 0 was filled (status image bits 8-15).
DHR_CONST uint kClientFillNone = 0u;       // known, background, or unfilled (all bits: lit)
DHR_CONST uint kClientFillOtherEye = 1u;   // from source 1
DHR_CONST uint kClientFillShadowMap = 2u;  // from the shadow maps
DHR_CONST uint kClientFillOlder = 3u;      // from source 2 (this eye's previous buffer)
DHR_CONST uint kClientFillNeighbour = 4u;  // from the nearest source-0 pixel on the pixel's tangent plane
// Counted fields: statuses 0-6, then the fills and the pixels whose undecided bits took the shadow maps.
DHR_CONST uint kClientCountOtherEye = 7u;
DHR_CONST uint kClientCountShadowMap = 8u;
DHR_CONST uint kClientCountEdgeShadowMap = 9u;
DHR_CONST uint kClientCountShadowOverride = 10u;  // confident shadow-map bits that replaced agreed samples
DHR_CONST uint kClientCountOlder = 11u;
DHR_CONST uint kClientCountNeighbour = 12u;
DHR_CONST uint kClientCountMotion = 13u;  // surface pixels with bits motion made unknown (kClientWarpMotion)
DHR_CONST uint kClientCountFields = 14u;
DHR_CONST uint kClientCountWords = 5u;  // three 10-bit fields per word

// ClientWarpParams::flags
DHR_CONST uint kClientWarpWriteMotion = 4u;
DHR_CONST uint kClientWarpWriteStatus = 8u;
DHR_CONST uint kClientWarpBilinear = 16u;        // 2x2 samples around the lookup, bilinear vote
DHR_CONST uint kClientWarpDepthTest = 32u;       // samples off the pixel's tangent plane are rejected
DHR_CONST uint kClientWarpShadowFill = 64u;      // pixels without a source take the shadow maps
DHR_CONST uint kClientWarpShadowEdges = 128u;    // bits the samples disagree on take the shadow maps
DHR_CONST uint kClientWarpShadowFirst = 256u;    // bits the shadow maps are confident about take them
DHR_CONST uint kClientWarpOlderBuffer = 512u;    // pixels without a source so far try source 2
DHR_CONST uint kClientWarpNeighbourFill = 1024u; // ... then the nearest source-0 pixel on their tangent plane
DHR_CONST uint kClientWarpMotion = 2048u;        // bits that motion since a source's scene time may change: unknown
DHR_CONST uint kClientWarpSoftRefine = 4096u;    // soft fields' shares blended from the samples' band shares
// The neighbour fill searches the old pixels within this many pixels (Chebyshev) of the lookup's pixel.
DHR_CONST int kClientWarpNeighbourRadius = 2;
// Bilinear lookups within this many old pixels of an old pixel centre (in x and y) take that pixel's mask
// as exact: it was traced for this very ray (no motion since, or none that moved the lookup).
DHR_CONST float kClientWarpExactLookup = 0.02f;
// A soft field whose used samples' levels span more than this many levels (of kClientSoftLevels - 1) is an edge,
// not a penumbra: the 2x2 straddles a shadow boundary sharper than a pixel or two, where a blend of levels is as
// wrong as a hard bit's vote, so the field counts as undecided (bilinear_warp.h's warp_vote_fields). Only for the
// lights in ClientWarpParams::soft_edge_lights: a sun's (render/light_layout.hpp, soft_edge_light_mask).
DHR_CONST uint kClientWarpSoftEdgeSpread = 4u;
// Refined soft shares (kClientWarpSoftRefine; bilinear_warp.h's warp_soft_blend): the levels a soft field shows
// are its share rounded to kClientSoftLevels levels, which bands a smooth penumbra into contours. Each source's
// levels are reconstructed into band shares once (render/soft_bands.hpp, kClientSourceHasShares), and the warp
// blends the used samples' band shares whose level is within one of the vote's, for the first
// kClientSoftRefineFields soft fields, one byte each (share x kClientSoftRefineScale, rounded) in a uint;
// kClientSoftRefineNone in a byte: none, the mask's level holds.
DHR_CONST uint kClientSoftRefineFields = 4u;
DHR_CONST uint kClientSoftRefineScale = 254u;
DHR_CONST uint kClientSoftRefineNone = 255u;
DHR_CONST uint kClientSoftRefineNoneAll = 0xFFFFFFFFu;
// The band shares' table: two words per refined field per cell (the bytes of levels 0-3, 4-7).
DHR_CONST uint kClientSoftBandCellWords = 2u * kClientSoftRefineFields;
// The table made on the GPU (render/soft_band_pass.hpp, soft_bands.comp): three dispatches over the cells. Per cell
// and refined field the counts are eight 16-bit lanes, two to a word (kClientSoftBandLaneWords words per cell).
DHR_CONST uint kClientSoftBandBindingVisibility = 0;  // storage buffer uint[]: the masks; the table at share_word
DHR_CONST uint kClientSoftBandBindingRows = 1;        // storage buffer uint[]: bit r%32 of word r/32 = row r arrived
DHR_CONST uint kClientSoftBandBindingScratch = 2;     // storage buffer uint[]: per cell its counts and its levels,
                                                      // then from sum_word on the counts' row sums
DHR_CONST uint kClientSoftBandCount = 0u;   // ClientSoftBandPush::stage: each cell's counts and levels held
DHR_CONST uint kClientSoftBandRowSum = 1u;  // the counts summed over the row's cells within reach
DHR_CONST uint kClientSoftBandShares = 2u;  // those summed over the column's, and the table's bytes
DHR_CONST uint kClientSoftBandLaneWords = 4u * kClientSoftRefineFields;
DHR_CONST uint kClientSoftBandCountWords = kClientSoftBandLaneWords + 1u;  // + the levels held, a byte per field
struct ClientSoftBandPush {
  uint stage;       // kClientSoftBand*
  uint width;       // the buffer's pixels
  uint height;
  uint mask_bits;   // 8, 16 or 32
  uint cell_shift;  // cells of 2^cell_shift pixels square
  uint columns;     // cells per row
  uint rows;        // cell rows
  uint reach;       // the window: the cells within `reach` cells of a pixel's cell along each axis
  uint refined;     // bit r: field rank r has shares (its field offset in field_offset[r])
  uint has_rows;    // 1: rows not set in the row bits did not arrive (their pixels count for nothing)
  uint share_word;  // where the table starts in the visibility buffer
  uint sum_word;    // where the row sums start in the scratch buffer
  uint field_offset[4];  // kClientSoftRefineFields
};
// ClientWarpSource::flags
DHR_CONST uint kClientSourceHasVisibility = 1u;
DHR_CONST uint kClientSourceHasRowValidity = 2u;
DHR_CONST uint kClientSourceHasDepth = 4u;
DHR_CONST uint kClientSourceSameEye = 8u;  // traced from the display eye's position (rotation at most)
DHR_CONST uint kClientSourceHasEdges = 16u;  // edge band marks after the masks (ClientWarpSource::edge_word)
DHR_CONST uint kClientSourceHasShares = 32u;  // band shares after them (ClientWarpSource::share_word)
// Status counts are gathered per bucket of this many horizontally adjacent workgroups (8 x 64 pixels fit
// the 10-bit fields); field f is in the bucket's word f / 3, bits 10 * (f % 3).
DHR_CONST uint kClientCountBucketGroups = 8u;

// One source (a visibility buffer and the camera it was traced for). The pixel (i, j) of the display camera
// with depth-buffer value d is, in the old eye's space,
//   p_old = (near_plane / d) * (ray0 + (i + 0.5) * ray_dx + (j + 0.5) * ray_dy) + trans
// (ray0/ray_dx/ray_dy: R_old^T R_new applied to the display camera's tangent-plane point (tx, ty, -1) and its
// per-pixel steps), and lands at px = old_px_scale * p_old.x / -p_old.z + old_px_offset (same for y).
// The old pixel (a, b) looks along (old_tan_left + (a + 0.5) * old_tan_step_x, old_tan_up - (b + 0.5) *
// old_tan_step_y, -1); `rot` (row-major R_old^T) takes world normals into the old eye's space. Its traced depth
// (kClientSourceHasDepth) may be coarser: texel t = (a, b) / depth_scale looks along the same formula at the old
// pixel coordinate (t + 0.5) * depth_scale (bilinear_warp.h's warp_depth_point).
struct ClientWarpSource {
  float ray0[3];
  float ray_dx[3];
  float ray_dy[3];
  float trans[3];        // R_old^T * (eye_new - eye_old)
  float rot[9];
  float old_px_scale;
  float old_px_offset;
  float old_py_scale;
  float old_py_offset;
  float old_tan_left;
  float old_tan_up;
  float old_tan_step_x;
  float old_tan_step_y;
  uint old_width;        // old buffer size (guard band included); 1x1 without visibility
  uint old_height;
  uint mask_bits;        // 8, 16 or 32
  uint flags;            // kClientSource*
  uint depth_scale;      // kClientSourceHasDepth: one traced-depth texel per depth_scale x depth_scale old pixels
  uint edge_word;        // kClientSourceHasEdges: the edge band's marks (render/warp_edges.hpp) follow the masks in
                         // the source's buffer from this word on, packed as the masks are
  uint share_word;       // kClientSourceHasShares: the band shares' table (render/soft_bands.hpp's SoftBandTable:
                         // kClientSoftBandCellWords words per cell of 2^share_cell_shift old pixels square,
                         // share_columns cells per row) from this word on
  uint share_cell_shift;
  uint share_columns;
};

// Motion (kClientWarpMotion; DESIGN 5b): visibility traced at a source's scene time is trusted at the display's only
// where nothing that could change it moved (client/motion_rule.h; render/warp_motion.hpp fills these). Per source:
// the field bits of the lights placed differently at the two times, and the world boxes of the moved meshes at both
// times, relative to the display eye (world axes). A surface point inside a box (grown by receiver_margin) may lie
// on a moving surface: every bit unknown. Else a light's bits are unknown when the segment from the point towards
// the light meets a box grown by the light's growth (its extent: every shadow ray to it passes within that of the
// centre's). Unknown bits take the shadow maps as undecided ones do. Its own buffer (kClientWarpBindingMoved,
// kClientForwardBindingMoved), apart from ClientWarpParams, which the shader helpers take by value (its place did
// not change the cost measured in docs/motion.md: the per-pixel box tests are the cost).
DHR_CONST uint kClientMaxMotionBoxes = 16u;
struct ClientMotionSource {
  uint moved_bits;  // fields of the lights that moved
  uint box_count;   // > kClientMaxMotionBoxes: too many to list, every bit unknown
  uint pad0;
  uint pad1;
  float box_min[3 * 16];  // box b: [3b, 3b + 3)
  float box_max[3 * 16];
};
struct ClientMotionLight {
  float to_light[3];  // point-like: the light's centre; directional: the unit direction towards the light
  float growth;       // point-like: metres (the extent's radius); directional: tan of the angular radius
  uint field;         // its bits in the mask
  uint directional;   // 1: the segment runs far_distance towards the light
  uint pad0;
  uint pad1;
};
struct ClientWarpMotion {
  ClientMotionSource source[3];
  ClientMotionLight light[32];
  float far_distance;     // directional lights' segment length: the scene's bounding diagonal
  float receiver_margin;  // metres the boxes grow by for the receiver test
  uint enabled;           // 0: nothing moves (no test at all)
  uint pad;
};

// Shadow lookups: p_rel = (near_plane / d) * (world_ray0 + (i + 0.5) * world_ray_dx + (j + 0.5) * world_ray_dy)
// is the surface point relative to the display eye in world axes; the lights (kClientWarpBindingShadowLights)
// are relative to the same eye.
struct ClientWarpParams {
  ClientWarpSource source[3];
  float world_ray0[3];
  float world_ray_dx[3];
  float world_ray_dy[3];
  float ident_px_scale;  // lookup without any pose change (motion vectors only):
  float ident_px_offset; //   px = ident_px_scale * (i + 0.5) + ident_px_offset
  float ident_py_scale;
  float ident_py_offset;
  float near_plane;      // depth = near_plane / distance along the view axis
  float min_depth;       // old-eye depth at or below this: behind
  float plane_tolerance_rel;  // depth test: |distance to the tangent plane| <= rel * depth + abs
  float plane_tolerance_abs;
  float shadow_near;          // the shadow maps' near plane
  float shadow_bias_rel;      // lit when stored >= distance - (rel * distance + abs + slope term)
  float shadow_bias_abs;
  float shadow_normal_offset; // texels (at the point's distance) along the normal before the lookup
  float shadow_bias_slope;    // plus this many texels (at the point's distance) times tan(angle of N and L)
  float pixel_tangent;        // the display's tangent-space width of a pixel (its size per metre of depth)
  uint shadow_size;           // texels per face side
  uint width;            // display (G-buffer) size
  uint height;
  uint light_count;
  uint unknown_mask;     // mask for unfilled pixels: all light bits
  uint flags;            // kClientWarp*
  uint soft_lights;      // bit i: light i has a soft field (visibility_field.h); the bilinear vote blends its levels
  uint soft_edge_lights; // bit i: light i's soft field is an edge where its samples span > kClientWarpSoftEdgeSpread
  uint soft_refine_bits; // kClientWarpSoftRefine: the bits of the soft fields it refines (all but edge lights')
};

// A light as the warp's shadow lookup sees it: position relative to the display eye (world axes) and the
// first tile of its six cube faces in the atlas (row `tile_row`, faces in columns 0-5); kClientNoShadowMap
// where the light has none (directional lights: such bits are taken as lit).
DHR_CONST uint kClientNoShadowMap = 0xFFFFFFFFu;
// Where a light's visibility sits in the mask (visibility/visibility_layout.hpp): mask_offset is its first bit,
// mask_bits 1 (hard: the bit) or kClientSoftBits (soft: the Gray code of its level, kClientSoftLevels levels).
// A soft light's map lookup is PCSS (client/pcss.h) with the light's representative radius `radius` (metres;
// 0 for a hard light).
DHR_CONST uint kClientSoftBits = 3u;
DHR_CONST uint kClientSoftLevels = 8u;
// A sun (a directional light with an angle; kClientShadowSun in `flags`) has a fitted orthographic map instead
// of a cube: one size x size tile in column 0 of its row, covering the scene's bounds, looking along
// cross(up, right) from `position` (the centre of its near plane); stored depth = 1 - distance / depth_range
// (0: nothing); `radius` is tan of the sun's angular radius.
DHR_CONST uint kClientShadowSun = 1u;
struct ClientShadowLight {
  float position[3];
  uint tile_row;
  float radius;
  uint mask_offset;
  uint mask_bits;
  uint flags;          // kClientShadowSun
  float right[3];      // sun: the map's axes (world, unit) and half its side in metres
  float half_extent;
  float up[3];
  float depth_range;   // sun: metres from `position` to the far plane
};
// PCSS (client/pcss.h): a blocker search over a kClientPcssSearchGrid^2 grid of taps, then a PCF filter over a
// kClientPcssFilterGrid^2 grid, both radii (in texels) clamped to [kClientPcssMinRadius, kClientPcssMaxRadius].
DHR_CONST uint kClientPcssSearchGrid = 4u;   // 16 taps
DHR_CONST uint kClientPcssFilterGrid = 5u;   // 25 taps
DHR_CONST float kClientPcssMinRadius = 0.5f;
DHR_CONST float kClientPcssMaxRadius = 32.0f;

// Shading (compute, 8x8 groups).
DHR_CONST uint kClientShadingBindingDepth = 0;   // sampler2D
DHR_CONST uint kClientShadingBindingNormal = 1;  // sampler2D (RGBA16F world-space normal)
DHR_CONST uint kClientShadingBindingAlbedo = 2;  // sampler2D (RGBA8 linear albedo)
DHR_CONST uint kClientShadingBindingMask = 3;    // r32ui image (predicted mask)
DHR_CONST uint kClientShadingBindingStatus = 4;  // r32ui image (kClientStatus*)
DHR_CONST uint kClientShadingBindingMotion = 5;  // rg32f image (debug view only)
DHR_CONST uint kClientShadingBindingLights = 6;  // storage buffer PackedLight[] (eye-relative positions)
DHR_CONST uint kClientShadingBindingOutput = 7;  // rgba8 image (sRGB-encoded bytes in a UNORM image)
// uint[]: with kClientShadingLightSlots, the light slots (LightSlots::gpu_words: the server's format; the origin
// words are not read, ClientShadingPush::slot_origin_mm gives the grid's origin relative to the eye).
DHR_CONST uint kClientShadingBindingLightSlots = 8;
DHR_CONST uint kClientShadingBindingSoft = 9;    // r32ui image (refined soft shares; kClientShadingSoftRefined)

DHR_CONST uint kClientViewShaded = 0u;         // the shading equation, exposure, tonemap, sRGB
DHR_CONST uint kClientViewLightVisibility = 1u;  // light debug_light: white lit, black shadowed, red unknown
DHR_CONST uint kClientViewUnknown = 2u;        // shaded; pixels not from their own eye tinted by fill (magenta: lit)
DHR_CONST uint kClientViewAlbedo = 3u;
DHR_CONST uint kClientViewNormal = 4u;         // world normal * 0.5 + 0.5
DHR_CONST uint kClientViewMotion = 5u;         // motion vectors: red/green = +x/+y pixels (scaled)

DHR_CONST uint kClientShadingSwapRedBlue = 1u;  // store (b, g, r): bytes for a B8G8R8A8 swapchain copy
// The mask's fields are light slots (scene/light_slots.hpp): field f shades the light slot f holds in the cell of
// the pixel's surface point (kClientShadingBindingLightSlots), light_count and soft_lights count fields.
DHR_CONST uint kClientShadingLightSlots = 2u;
// The warp refined soft shares (kClientWarpSoftRefine): the shading reads them (kClientShadingBindingSoft).
DHR_CONST uint kClientShadingSoftRefined = 4u;

// The surface point of pixel (i, j) with depth-buffer value d, relative to the eye in world axes:
//   p = (near_plane / d) * (ray0 + (i + 0.5) * ray_dx + (j + 0.5) * ray_dy)

struct ClientShadingPush {
  float ray0[3];         // R_new * (left, up, -1)
  float ray_dx[3];       // R_new * (tangent width / width, 0, 0)
  float ray_dy[3];       // R_new * (0, -tangent height / height, 0)
  float near_plane;
  float exposure;        // linear scale before the tonemap
  float background_r;    // display-referred background colour (before sRGB encoding)
  float background_g;
  float background_b;
  uint width;
  uint height;
  uint light_count;
  uint view_mode;        // kClientView*
  uint debug_light;      // light index for kClientViewLightVisibility
  uint flags;            // kClientShading*
  uint soft_lights;      // bit i: light i has a soft field in the mask (client/visibility_field.h)
  float slot_origin_mm[3];  // kClientShadingLightSlots: the slot grid's origin relative to the eye, mm (world axes)
};

// Forward (graphics, forward*.frag over client/forward_body.h; set 0 = the G-buffer's per-material set): rasterizes and shades in one pass.
// The surface point of a fragment is reconstructed from gl_FragCoord exactly as the compute passes reconstruct
// it from the depth image, so the warp decisions are the compute warp's. Set 1:
DHR_CONST uint kClientForwardBindingParams = 0;        // storage buffer ClientWarpParams (rays, source 0, shadows)
DHR_CONST uint kClientForwardBindingVisibility0 = 1;   // storage buffer uint[]: source 0's packed masks
DHR_CONST uint kClientForwardBindingRowValid0 = 2;     // storage buffer uint[]: source 0's row validity
DHR_CONST uint kClientForwardBindingShadowMap = 3;     // sampler2D: shadow map atlas
DHR_CONST uint kClientForwardBindingShadowLights = 4;  // storage buffer ClientShadowLight[]
DHR_CONST uint kClientForwardBindingLights = 5;        // storage buffer PackedLight[] (display-eye-relative)
DHR_CONST uint kClientForwardBindingShading = 6;       // storage buffer ClientForwardShading
DHR_CONST uint kClientForwardBindingTracedDepth0 = 7;
DHR_CONST uint kClientForwardBindingLightSlots = 9;    // storage buffer uint[]: LightSlots::gpu_words (kClientForwardLambert with light slots)
DHR_CONST uint kClientForwardBindingMoved = 8;         // storage buffer ClientWarpMotion (kServerEdges, motion rule)  // sampler2D: source 0's traced depth (kServerEdges, depth test)
DHR_CONST uint kClientForwardLambert = 0u;     // every light bit set: Lambert without shadows
DHR_CONST uint kClientForwardShadowMaps = 1u;  // the mask of the client's shadow maps (shadow_lookup.h)
DHR_CONST uint kClientForwardPaperWarp = 2u;   // the paper's warp of source 0 (paper_warp.h); writes the status
// Server bits first (WarpSettings::server_edges): source 0's 2x2 bilinear samples (bilinear_warp.h); bits they
// disagree on and pixels without a sample from the shadow maps. With kClientWarpDepthTest and source 0's traced
// depth, samples off the pixel's tangent plane are not used (all off: disoccluded). Writes the status.
DHR_CONST uint kClientForwardServerEdges = 3u;
// Colour attachment 0: display-encoded bytes (RGBA8 UNORM); 1: R8_UINT status (kClientStatus*, with these
// flags; the count pass sums it); 2 (optional, tests): R32_UINT mask.
DHR_CONST uint kClientForwardStatusShadowFill = 16u;  // an unknown pixel took the shadow maps (kClientFillShadowMap)
DHR_CONST uint kClientForwardStatusShadowEdge = 32u;  // a known pixel's undecided bits took the shadow maps
DHR_CONST uint kClientForwardStatusMotion = 64u;      // a known pixel's bits motion made unknown (kClientWarpMotion)
DHR_CONST uint kClientForwardStatusMask = 15u;        // the kClientStatus* part
struct ClientForwardShading {
  float exposure;
  uint mode;             // kClientForward*
  uint flags;            // kClientShading* (swap red and blue)
  uint light_count;
  uint soft_lights;      // bit i: light i has a soft field in the mask (client/visibility_field.h)
  float slot_origin_mm[3];  // kClientShadingLightSlots: the slot grid's origin relative to the eye, mm (world axes)
};

#ifdef __cplusplus
static_assert(sizeof(ClientGBufferPush) == 128, "push constants must match the GLSL layout and fit the Vulkan minimum (128 bytes)");
static_assert(sizeof(ClientWarpSource) == 152, "ClientWarpSource must match the std430 layout");
static_assert(sizeof(ClientMotionSource) == 16 + 2 * 4 * 48, "ClientMotionSource must match the std430 layout");
static_assert(sizeof(ClientMotionLight) == 32, "ClientMotionLight must match the std430 array stride");
static_assert(sizeof(ClientWarpMotion) == 3 * sizeof(ClientMotionSource) + 32 * 32 + 16,
              "ClientWarpMotion must match the std430 layout");
static_assert(sizeof(ClientWarpParams) == 3 * 152 + 4 * 32, "ClientWarpParams must match the std430 layout");
static_assert(sizeof(ClientShadowLight) == 64, "ClientShadowLight must match the std430 array stride");
static_assert(sizeof(ClientShadingPush) == 96, "push constants must match the GLSL layout");
static_assert(sizeof(ClientSoftBandPush) == 64 && kClientSoftRefineFields == 4,
              "push constants must match the GLSL layout, one field offset per refined field");
static_assert(sizeof(ClientForwardShading) == 32, "ClientForwardShading must match the std430 layout");
}  // namespace dhr::shader
#endif

#undef DHR_CONST
#endif  // DHR_SHADER_INTERFACE_H
