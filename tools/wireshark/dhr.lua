-- Wireshark / tshark dissector for the DHR-XR wire protocol, version 7 (docs/protocol.md).
-- Load:  tshark -X lua_script:tools/wireshark/dhr.lua -r capture.pcapng -Y dhr
--        (Wireshark: copy to ~/.local/lib/wireshark/plugins/ or pass -X lua_script:...)
-- A heuristic dissector on UDP: every datagram that starts with "DHRX". Each message type and field is
-- decoded; sealed bodies (flags 1) are shown as ciphertext and tag, handshake tags (flags 2) as random and
-- tag after the body. Anything that does not fit its layout is flagged malformed (expert info), never
-- decoded past the point where it stops fitting. The layouts below are data generated from the protocol's
-- one field list (shared/protocol/include/protocol/wire_layout.hpp); the code walks them.

-- BEGIN LAYOUT: written by `dhr-protocol-layout --update-wireshark tools/wireshark/dhr.lua` from
-- shared/protocol/include/protocol/wire_layout.hpp (ProtocolLayout.WiresharkLayoutIsCurrent checks it).
-- Per field: { offset, wire type, name }; offsets from the datagram's start (the View's from its own).
local VERSION = 7
local MAX_DATAGRAM = 1280
local SEAL_TAG = 16
local HEADER = { size = 20, fields = {
  { 0, "u8 x4", "magic" },
  { 4, "u8", "version" },
  { 5, "u8", "type" },
  { 6, "u16", "flags" },
  { 8, "u64", "session_token" },
  { 16, "u32", "sequence" },
} }
local VIEW = { size = 56, fields = {
  { 0, "f64 x3", "position" },
  { 24, "f32 x4", "orientation" },
  { 40, "f32 x4", "fov" },
} }
local MESSAGES = {
  [1] = { name = "Hello", size = 42, tail_length = "scene_id_length", fields = {
    { 20, "u64", "client_nonce" },
    { 28, "u32", "capabilities" },
    { 32, "u16", "eye_width" },
    { 34, "u16", "eye_height" },
    { 36, "u16", "guard_x" },
    { 38, "u16", "guard_y" },
    { 40, "u8", "light_count_wanted" },
    { 41, "u8", "scene_id_length" },
    { 42, "u8[n]", "scene_id" },
  } },
  [3] = { name = "PoseUpdate", size = 160, fields = {
    { 20, "u64", "frame" },
    { 28, "i64", "display_time_ns" },
    { 36, "i64", "scene_time_ns" },
    { 44, "View", "left_view" },
    { 100, "View", "right_view" },
    { 156, "u16 x2", "held_distance" },
  } },
  [7] = { name = "NodeTransform", size = 84, fields = {
    { 20, "u32", "node" },
    { 24, "i64", "scene_time_ns" },
    { 32, "f64 x3", "translation" },
    { 56, "f32 x4", "rotation" },
    { 72, "f32 x3", "scale" },
  } },
  [2] = { name = "Welcome", size = 57, fields = {
    { 20, "u64", "client_nonce" },
    { 28, "u32", "capabilities" },
    { 32, "u64", "scene_hash" },
    { 40, "u8", "light_count" },
    { 41, "u8", "mask_bits" },
    { 42, "u8", "soft_light_count" },
    { 43, "u16", "buffer_width" },
    { 45, "u16", "buffer_height" },
    { 47, "u16", "guard_x" },
    { 49, "u16", "guard_y" },
    { 51, "u16", "heartbeat_interval_ms" },
    { 53, "u32", "session_timeout_ms" },
  } },
  [4] = { name = "VisibilityShard", size = 112, tail_length = "payload_size", fields = {
    { 20, "u64", "frame_number" },
    { 28, "u8", "eye" },
    { 29, "u8", "mask_bits" },
    { 30, "u16", "shard_index" },
    { 32, "u16", "shard_count" },
    { 34, "u16", "buffer_width" },
    { 36, "u16", "buffer_height" },
    { 38, "u16", "payload_size" },
    { 40, "u32", "first_pixel" },
    { 44, "u32", "pixel_count" },
    { 48, "i64", "scene_time_ns" },
    { 56, "View", "view" },
    { 112, "u8[p]", "payload" },
  } },
  [5] = { name = "Heartbeat", size = 72, fields = {
    { 20, "i64", "send_time_ns" },
    { 28, "i64", "echo_time_ns" },
    { 36, "i64", "echo_delay_ns" },
    { 44, "u64", "newest_frame" },
    { 52, "u32", "datagrams_sent" },
    { 56, "u32", "datagrams_received" },
    { 60, "u32", "datagrams_rejected" },
    { 64, "u32", "frames_done" },
    { 68, "u32", "frames_dropped" },
  } },
  [6] = { name = "Bye", size = 21, fields = {
    { 20, "u8", "reason" },
  } },
}
-- END LAYOUT

local dhr = Proto("dhr", "DHR-XR visibility protocol")

local types = {}
for id, m in pairs(MESSAGES) do types[id] = m.name end
local reasons = { [0] = "normal", [1] = "timeout", [2] = "protocol error", [3] = "shutdown",
                  [4] = "version mismatch", [5] = "unknown session", [6] = "bad hello", [7] = "unknown scene",
                  [8] = "authentication required", [9] = "authentication failed" }
local eyes = { [0] = "left", [1] = "right" }

-- One filter field per layout field name (a name in several messages, like guard_x, shares one).
local f = {
  magic = ProtoField.string("dhr.magic", "Magic"),
  version = ProtoField.uint8("dhr.version", "Version"),
  type = ProtoField.uint8("dhr.type", "Type", base.DEC, types),
  flags = ProtoField.uint16("dhr.flags", "Flags", base.HEX),
  sealed = ProtoField.bool("dhr.flags.sealed", "Sealed", 16, nil, 0x0001),
  tagged = ProtoField.bool("dhr.flags.handshake_tag", "Handshake tag", 16, nil, 0x0002),
  session_token = ProtoField.uint64("dhr.token", "Session token", base.HEX),
  sequence = ProtoField.uint32("dhr.sequence", "Sequence"),
  client_nonce = ProtoField.uint64("dhr.nonce", "Client nonce", base.HEX),
  capabilities = ProtoField.uint32("dhr.capabilities", "Capabilities", base.HEX),
  eye_width = ProtoField.uint16("dhr.eye_width", "Eye width"),
  eye_height = ProtoField.uint16("dhr.eye_height", "Eye height"),
  guard_x = ProtoField.uint16("dhr.guard_x", "Guard x"),
  guard_y = ProtoField.uint16("dhr.guard_y", "Guard y"),
  light_count_wanted = ProtoField.uint8("dhr.lights_wanted", "Lights wanted"),
  scene_id_length = ProtoField.uint8("dhr.scene_id_length", "Scene id length"),
  scene_id = ProtoField.string("dhr.scene_id", "Scene id"),
  scene_hash = ProtoField.uint64("dhr.scene_hash", "Scene hash", base.HEX),
  light_count = ProtoField.uint8("dhr.light_count", "Light count"),
  mask_bits = ProtoField.uint8("dhr.mask_bits", "Mask bits"),
  soft_light_count = ProtoField.uint8("dhr.soft_light_count", "Lights with soft levels"),
  buffer_width = ProtoField.uint16("dhr.buffer_width", "Buffer width"),
  buffer_height = ProtoField.uint16("dhr.buffer_height", "Buffer height"),
  heartbeat_interval_ms = ProtoField.uint16("dhr.heartbeat_ms", "Heartbeat interval (ms)"),
  session_timeout_ms = ProtoField.uint32("dhr.timeout_ms", "Session timeout (ms)"),
  frame = ProtoField.uint64("dhr.frame", "Frame"),
  display_time_ns = ProtoField.int64("dhr.display_time_ns", "Display time (ns)"),
  scene_time_ns = ProtoField.int64("dhr.scene_time_ns", "Scene time (ns)"),
  view = ProtoField.none("dhr.view", "View"),
  position = ProtoField.string("dhr.view.position", "Position (m)"),
  orientation = ProtoField.string("dhr.view.orientation", "Orientation (x, y, z, w)"),
  fov = ProtoField.string("dhr.view.fov", "FOV (left, right, up, down; rad)"),
  held_distance = ProtoField.uint16("dhr.held_distance", "Held distance"),
  eye = ProtoField.uint8("dhr.eye", "Eye", base.DEC, eyes),
  shard_index = ProtoField.uint16("dhr.shard_index", "Shard index"),
  shard_count = ProtoField.uint16("dhr.shard_count", "Shard count"),
  payload_size = ProtoField.uint16("dhr.payload_size", "Payload size"),
  first_pixel = ProtoField.uint32("dhr.first_pixel", "First pixel"),
  pixel_count = ProtoField.uint32("dhr.pixel_count", "Pixel count"),
  payload = ProtoField.bytes("dhr.payload", "Payload"),
  send_time_ns = ProtoField.int64("dhr.send_time_ns", "Send time (ns)"),
  echo_time_ns = ProtoField.int64("dhr.echo_time_ns", "Echo time (ns)"),
  echo_delay_ns = ProtoField.int64("dhr.echo_delay_ns", "Echo delay (ns)"),
  newest_frame = ProtoField.uint64("dhr.newest_frame", "Newest frame"),
  datagrams_sent = ProtoField.uint32("dhr.datagrams_sent", "Datagrams sent"),
  datagrams_received = ProtoField.uint32("dhr.datagrams_received", "Datagrams received"),
  datagrams_rejected = ProtoField.uint32("dhr.datagrams_rejected", "Datagrams rejected"),
  frames_done = ProtoField.uint32("dhr.frames_done", "Frames done"),
  frames_dropped = ProtoField.uint32("dhr.frames_dropped", "Frames dropped"),
  reason = ProtoField.uint8("dhr.reason", "Reason", base.DEC, reasons),
  node = ProtoField.uint32("dhr.node", "Node (glTF index)"),
  translation = ProtoField.string("dhr.node.translation", "Translation (m)"),
  rotation = ProtoField.string("dhr.node.rotation", "Rotation (x, y, z, w)"),
  scale = ProtoField.string("dhr.node.scale", "Scale"),
  ciphertext = ProtoField.bytes("dhr.ciphertext", "Sealed body"),
  seal_tag = ProtoField.bytes("dhr.seal_tag", "Seal tag (Poly1305)"),
  random = ProtoField.bytes("dhr.random", "Handshake random"),
  hs_tag = ProtoField.bytes("dhr.handshake_tag", "Handshake tag (HMAC-SHA-512-256)"),
}
dhr.fields = {}
for _, field in pairs(f) do table.insert(dhr.fields, field) end
-- Layout names shown under another's filter field (registered once above).
f.frame_number = f.frame
f.left_view = f.view
f.right_view = f.view
-- A layout field without a filter field is a bug in this file: say so when it loads, not mid-capture.
local function check_names(block)
  for _, fl in ipairs(block.fields) do assert(f[fl[3]], "dhr.lua: no filter field for layout field " .. fl[3]) end
end
check_names(HEADER)
check_names(VIEW)
for _, m in pairs(MESSAGES) do check_names(m) end

local e_malformed = ProtoExpert.new("dhr.malformed", "Malformed DHR datagram", expert.group.MALFORMED,
                                    expert.severity.ERROR)
local e_version = ProtoExpert.new("dhr.other_version", "Another protocol version (only its header is decoded)",
                                  expert.group.PROTOCOL, expert.severity.WARN)
dhr.experts = { e_malformed, e_version }

local HS_TRAILER = 64  -- a handshake tag's random and tag (docs/protocol.md, "Authentication")
local SIZE = { u8 = 1, u16 = 2, u32 = 4, u64 = 8, i64 = 8, f32 = 4, f64 = 8 }

local function malformed(tree, tvb, why)
  tree:add_proto_expert_info(e_malformed, why)
  return false
end

-- "u16" -> "u16", 1; "f32 x4" -> "f32", 4; "u8[n]" -> "tail", 1; "View" -> "View", 1.
local function split_type(t)
  local base, n = t:match("^(%w+) x(%d+)$")
  if base then return base, tonumber(n) end
  if t:match("^u8%[") then return "tail", 1 end
  return t, 1
end

local function field_named(block, name)
  for _, fl in ipairs(block.fields) do if fl[3] == name then return fl end end
end

-- Adds a layout's fields at origin + offset; returns the values of the integer fields (by name) and the
-- items added (by name). tail_len: bytes of the tail, if the layout has one.
local function add_fields(tree, tvb, fields, origin, tail_len)
  local values, items = {}, {}
  for _, fl in ipairs(fields) do
    local at, key = origin + fl[1], fl[3]
    local base, n = split_type(fl[2])
    if base == "View" then
      items[key] = tree:add(f[key], tvb(at, VIEW.size))
      add_fields(items[key], tvb, VIEW.fields, at, 0)
    elseif base == "tail" then
      if tail_len > 0 then items[key] = tree:add(f[key], tvb(at, tail_len)) end
    elseif base == "f32" or base == "f64" then
      local size, shown = SIZE[base], {}
      for i = 0, n - 1 do shown[#shown + 1] = string.format("%.6f", tvb(at + i * size, size):le_float()) end
      items[key] = tree:add(f[key], tvb(at, n * size), table.concat(shown, ", "))
    elseif base == "u8" and n > 1 then
      items[key] = tree:add(f[key], tvb(at, n))
    else
      local size = SIZE[base]
      for i = 0, n - 1 do items[key] = tree:add_le(f[key], tvb(at + i * size, size)) end
      if n == 1 and size <= 4 then values[key] = tvb(at, size):le_uint() end
    end
  end
  return values, items
end

-- What a layout cannot say: values that make a datagram that fits its layout malformed anyway.
local CHECKS = {
  VisibilityShard = function(v)
    if v.shard_index >= v.shard_count then return "VisibilityShard: shard index not below the count" end
  end,
  Bye = function(v)
    if reasons[v.reason] == nil then return "Bye: unknown reason " .. v.reason end
  end,
}

-- Decodes the body of a plain message in tvb(0, len); false (flagged) when it does not fit its layout.
local function dissect_body(kind, tvb, len, tree)
  local m = MESSAGES[kind]
  local tail_len = 0
  if m.tail_length then
    if len < m.size then return malformed(tree, tvb, m.name .. " shorter than " .. m.size .. " bytes") end
    local lf = field_named(m, m.tail_length)
    tail_len = tvb(lf[1], SIZE[lf[2]]):le_uint()
    if len ~= m.size + tail_len then
      return malformed(tree, tvb,
                       m.name .. ": " .. m.tail_length .. " " .. tail_len .. " does not fit " .. len .. " bytes")
    end
  elseif len ~= m.size then
    return malformed(tree, tvb, m.name .. ": " .. len .. " bytes, expected " .. m.size)
  end
  local values = add_fields(tree, tvb, m.fields, 0, tail_len)
  local why = CHECKS[m.name] and CHECKS[m.name](values)
  if why then return malformed(tree, tvb, why) end
  return true
end

local function dissect(tvb, pinfo, root)
  local len = tvb:len()
  local magic = field_named(HEADER, "magic")
  if len < 4 or tvb(magic[1], 4):string() ~= "DHRX" then return false end
  pinfo.cols.protocol = "DHR"
  local tree = root:add(dhr, tvb(), "DHR-XR")
  if len < HEADER.size then
    tree:add(f.magic, tvb(magic[1], 4))
    malformed(tree, tvb, "shorter than the " .. HEADER.size .. "-byte header")
    pinfo.cols.info = "DHR malformed (short)"
    return true
  end
  local h, items = add_fields(tree, tvb, HEADER.fields, 0, 0)
  local flags_at = field_named(HEADER, "flags")[1]
  items.flags:add_le(f.sealed, tvb(flags_at, 2))
  items.flags:add_le(f.tagged, tvb(flags_at, 2))
  local kind = h.type
  local name = types[kind] or ("type " .. kind)
  pinfo.cols.info = "DHR " .. name
  if h.version ~= VERSION then
    tree:add_proto_expert_info(e_version, "version " .. h.version)
    return true
  end
  if types[kind] == nil then
    malformed(tree, tvb, "unknown message type " .. kind)
    return true
  end
  if len > MAX_DATAGRAM then malformed(tree, tvb, "longer than " .. MAX_DATAGRAM .. " bytes") return true end
  local flags = h.flags
  if flags == 1 then
    if len < HEADER.size + SEAL_TAG then
      malformed(tree, tvb, "sealed datagram without room for its tag")
      return true
    end
    if len > HEADER.size + SEAL_TAG then tree:add(f.ciphertext, tvb(HEADER.size, len - HEADER.size - SEAL_TAG)) end
    tree:add(f.seal_tag, tvb(len - SEAL_TAG, SEAL_TAG))
    pinfo.cols.info = "DHR " .. name .. " (sealed)"
    return true
  end
  local body_len = len
  if flags == 2 then
    if len < HEADER.size + HS_TRAILER then malformed(tree, tvb, "handshake tag missing") return true end
    body_len = len - HS_TRAILER
    pinfo.cols.info = "DHR " .. name .. " (tagged)"
  elseif flags ~= 0 then
    malformed(tree, tvb, string.format("unknown flags 0x%04x", flags))
    return true
  end
  local ok = dissect_body(kind, tvb(0, body_len):tvb(), body_len, tree)
  if flags == 2 then
    tree:add(f.random, tvb(body_len, 32))
    tree:add(f.hs_tag, tvb(body_len + 32, 32))
  end
  if not ok then pinfo.cols.info = "DHR " .. name .. " (malformed)" end
  return true
end

dhr:register_heuristic("udp", dissect)
