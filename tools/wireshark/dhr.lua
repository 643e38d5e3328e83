-- Wireshark / tshark dissector for the DHR-XR wire protocol, version 3 (docs/protocol.md).
-- Load:  tshark -X lua_script:tools/wireshark/dhr.lua -r capture.pcapng -Y dhr
--        (Wireshark: copy to ~/.local/lib/wireshark/plugins/ or pass -X lua_script:...)
-- A heuristic dissector on UDP: every datagram that starts with "DHRX". Each message type and field is
-- decoded; sealed bodies (flags 1) are shown as ciphertext and tag, handshake tags (flags 2) as random and
-- tag after the body. Anything that does not fit its layout is flagged malformed (expert info), never
-- decoded past the point where it stops fitting.

local dhr = Proto("dhr", "DHR-XR visibility protocol")

local types = { [1] = "Hello", [2] = "Welcome", [3] = "PoseUpdate", [4] = "VisibilityShard", [5] = "Heartbeat",
                [6] = "Bye" }
local reasons = { [0] = "normal", [1] = "timeout", [2] = "protocol error", [3] = "shutdown",
                  [4] = "version mismatch", [5] = "unknown session", [6] = "bad hello", [7] = "unknown scene",
                  [8] = "authentication required", [9] = "authentication failed" }
local eyes = { [0] = "left", [1] = "right" }

local f = {
  magic = ProtoField.string("dhr.magic", "Magic"),
  version = ProtoField.uint8("dhr.version", "Version"),
  type = ProtoField.uint8("dhr.type", "Type", base.DEC, types),
  flags = ProtoField.uint16("dhr.flags", "Flags", base.HEX),
  sealed = ProtoField.bool("dhr.flags.sealed", "Sealed", 16, nil, 0x0001),
  tagged = ProtoField.bool("dhr.flags.handshake_tag", "Handshake tag", 16, nil, 0x0002),
  token = ProtoField.uint64("dhr.token", "Session token", base.HEX),
  sequence = ProtoField.uint32("dhr.sequence", "Sequence"),
  nonce = ProtoField.uint64("dhr.nonce", "Client nonce", base.HEX),
  caps = ProtoField.uint32("dhr.capabilities", "Capabilities", base.HEX),
  eye_width = ProtoField.uint16("dhr.eye_width", "Eye width"),
  eye_height = ProtoField.uint16("dhr.eye_height", "Eye height"),
  guard_x = ProtoField.uint16("dhr.guard_x", "Guard x"),
  guard_y = ProtoField.uint16("dhr.guard_y", "Guard y"),
  lights_wanted = ProtoField.uint8("dhr.lights_wanted", "Lights wanted"),
  scene_id = ProtoField.string("dhr.scene_id", "Scene id"),
  scene_hash = ProtoField.uint64("dhr.scene_hash", "Scene hash", base.HEX),
  light_count = ProtoField.uint8("dhr.light_count", "Light count"),
  mask_bits = ProtoField.uint8("dhr.mask_bits", "Mask bits"),
  buffer_width = ProtoField.uint16("dhr.buffer_width", "Buffer width"),
  buffer_height = ProtoField.uint16("dhr.buffer_height", "Buffer height"),
  heartbeat_ms = ProtoField.uint16("dhr.heartbeat_ms", "Heartbeat interval (ms)"),
  timeout_ms = ProtoField.uint32("dhr.timeout_ms", "Session timeout (ms)"),
  frame = ProtoField.uint64("dhr.frame", "Frame"),
  display_time = ProtoField.int64("dhr.display_time_ns", "Display time (ns)"),
  view = ProtoField.none("dhr.view", "View"),
  position = ProtoField.string("dhr.view.position", "Position (m)"),
  orientation = ProtoField.string("dhr.view.orientation", "Orientation (x, y, z, w)"),
  fov = ProtoField.string("dhr.view.fov", "FOV (left, right, up, down; rad)"),
  held = ProtoField.uint16("dhr.held_distance", "Held distance"),
  eye = ProtoField.uint8("dhr.eye", "Eye", base.DEC, eyes),
  shard_index = ProtoField.uint16("dhr.shard_index", "Shard index"),
  shard_count = ProtoField.uint16("dhr.shard_count", "Shard count"),
  payload_size = ProtoField.uint16("dhr.payload_size", "Payload size"),
  first_pixel = ProtoField.uint32("dhr.first_pixel", "First pixel"),
  pixel_count = ProtoField.uint32("dhr.pixel_count", "Pixel count"),
  payload = ProtoField.bytes("dhr.payload", "Payload"),
  send_time = ProtoField.int64("dhr.send_time_ns", "Send time (ns)"),
  echo_time = ProtoField.int64("dhr.echo_time_ns", "Echo time (ns)"),
  echo_delay = ProtoField.int64("dhr.echo_delay_ns", "Echo delay (ns)"),
  newest_frame = ProtoField.uint64("dhr.newest_frame", "Newest frame"),
  counter = ProtoField.uint32("dhr.counter", "Counter"),
  reason = ProtoField.uint8("dhr.reason", "Reason", base.DEC, reasons),
  ciphertext = ProtoField.bytes("dhr.ciphertext", "Sealed body"),
  seal_tag = ProtoField.bytes("dhr.seal_tag", "Seal tag (Poly1305)"),
  random = ProtoField.bytes("dhr.random", "Handshake random"),
  hs_tag = ProtoField.bytes("dhr.handshake_tag", "Handshake tag (HMAC-SHA-512-256)"),
}
dhr.fields = {}
for _, field in pairs(f) do table.insert(dhr.fields, field) end

local e_malformed = ProtoExpert.new("dhr.malformed", "Malformed DHR datagram", expert.group.MALFORMED,
                                    expert.severity.ERROR)
local e_version = ProtoExpert.new("dhr.other_version", "Another protocol version (only its header is decoded)",
                                  expert.group.PROTOCOL, expert.severity.WARN)
dhr.experts = { e_malformed, e_version }

local HEADER = 20
local VIEW = 56
local SEAL_TAG = 16
local HS_TRAILER = 64
local BODY = { [2] = 36, [3] = 16 + 2 * VIEW + 4, [5] = 52, [6] = 1 }  -- fixed body sizes (Hello, Shard vary)

local function malformed(tree, tvb, why)
  tree:add_proto_expert_info(e_malformed, why)
  return false
end

local function add_view(tree, tvb, at)
  local v = tree:add(f.view, tvb(at, VIEW))
  v:add(f.position, tvb(at, 24), string.format("%.6f, %.6f, %.6f", tvb(at, 8):le_float(), tvb(at + 8, 8):le_float(),
                                                 tvb(at + 16, 8):le_float()))
  v:add(f.orientation, tvb(at + 24, 16), string.format("%.6f, %.6f, %.6f, %.6f", tvb(at + 24, 4):le_float(),
                                                         tvb(at + 28, 4):le_float(), tvb(at + 32, 4):le_float(),
                                                         tvb(at + 36, 4):le_float()))
  v:add(f.fov, tvb(at + 40, 16), string.format("%.6f, %.6f, %.6f, %.6f", tvb(at + 40, 4):le_float(),
                                                 tvb(at + 44, 4):le_float(), tvb(at + 48, 4):le_float(),
                                                 tvb(at + 52, 4):le_float()))
end

-- Decodes the body of a plain message in tvb(HEADER, len - HEADER); false (flagged) when it does not fit.
local function dissect_body(kind, tvb, len, tree)
  local b = HEADER
  local size = len - HEADER
  if kind == 1 then
    if size < 22 then return malformed(tree, tvb, "Hello shorter than 42 bytes") end
    local n = tvb(b + 21, 1):uint()
    if size ~= 22 + n then return malformed(tree, tvb, "Hello: scene id length " .. n .. " does not fit " .. len .. " bytes") end
    tree:add_le(f.nonce, tvb(b, 8)); tree:add_le(f.caps, tvb(b + 8, 4))
    tree:add_le(f.eye_width, tvb(b + 12, 2)); tree:add_le(f.eye_height, tvb(b + 14, 2))
    tree:add_le(f.guard_x, tvb(b + 16, 2)); tree:add_le(f.guard_y, tvb(b + 18, 2))
    tree:add(f.lights_wanted, tvb(b + 20, 1))
    if n > 0 then tree:add(f.scene_id, tvb(b + 22, n)) end
    return true
  end
  if kind == 4 then
    if size < 28 + VIEW then return malformed(tree, tvb, "VisibilityShard shorter than its 104-byte header") end
    local p = tvb(b + 18, 2):le_uint()
    if size ~= 28 + VIEW + p then
      return malformed(tree, tvb, "VisibilityShard: payload size " .. p .. " does not fit " .. len .. " bytes")
    end
    tree:add_le(f.frame, tvb(b, 8)); tree:add(f.eye, tvb(b + 8, 1)); tree:add(f.mask_bits, tvb(b + 9, 1))
    tree:add_le(f.shard_index, tvb(b + 10, 2)); tree:add_le(f.shard_count, tvb(b + 12, 2))
    tree:add_le(f.buffer_width, tvb(b + 14, 2)); tree:add_le(f.buffer_height, tvb(b + 16, 2))
    tree:add_le(f.payload_size, tvb(b + 18, 2)); tree:add_le(f.first_pixel, tvb(b + 20, 4))
    tree:add_le(f.pixel_count, tvb(b + 24, 4))
    add_view(tree, tvb, b + 28)
    if p > 0 then tree:add(f.payload, tvb(b + 28 + VIEW, p)) end
    if tvb(b + 10, 2):le_uint() >= tvb(b + 12, 2):le_uint() then
      return malformed(tree, tvb, "VisibilityShard: shard index not below the count")
    end
    return true
  end
  local want = BODY[kind]
  if size ~= want then
    return malformed(tree, tvb, (types[kind] or "?") .. ": " .. len .. " bytes, expected " .. (HEADER + want))
  end
  if kind == 2 then
    tree:add_le(f.nonce, tvb(b, 8)); tree:add_le(f.caps, tvb(b + 8, 4)); tree:add_le(f.scene_hash, tvb(b + 12, 8))
    tree:add(f.light_count, tvb(b + 20, 1)); tree:add(f.mask_bits, tvb(b + 21, 1))
    tree:add_le(f.buffer_width, tvb(b + 22, 2)); tree:add_le(f.buffer_height, tvb(b + 24, 2))
    tree:add_le(f.guard_x, tvb(b + 26, 2)); tree:add_le(f.guard_y, tvb(b + 28, 2))
    tree:add_le(f.heartbeat_ms, tvb(b + 30, 2)); tree:add_le(f.timeout_ms, tvb(b + 32, 4))
  elseif kind == 3 then
    tree:add_le(f.frame, tvb(b, 8)); tree:add_le(f.display_time, tvb(b + 8, 8))
    add_view(tree, tvb, b + 16); add_view(tree, tvb, b + 16 + VIEW)
    tree:add_le(f.held, tvb(b + 16 + 2 * VIEW, 2)); tree:add_le(f.held, tvb(b + 18 + 2 * VIEW, 2))
  elseif kind == 5 then
    tree:add_le(f.send_time, tvb(b, 8)); tree:add_le(f.echo_time, tvb(b + 8, 8)); tree:add_le(f.echo_delay, tvb(b + 16, 8))
    tree:add_le(f.newest_frame, tvb(b + 24, 8))
    for i = 0, 4 do tree:add_le(f.counter, tvb(b + 32 + 4 * i, 4)) end
  elseif kind == 6 then
    local r = tvb(b, 1):uint()
    tree:add(f.reason, tvb(b, 1))
    if reasons[r] == nil then return malformed(tree, tvb, "Bye: unknown reason " .. r) end
  end
  return true
end

local function dissect(tvb, pinfo, root)
  local len = tvb:len()
  if len < 4 or tvb(0, 4):string() ~= "DHRX" then return false end
  pinfo.cols.protocol = "DHR"
  local tree = root:add(dhr, tvb(), "DHR-XR")
  tree:add(f.magic, tvb(0, 4))
  if len < HEADER then
    malformed(tree, tvb, "shorter than the 20-byte header")
    pinfo.cols.info = "DHR malformed (short)"
    return true
  end
  local version = tvb(4, 1):uint()
  local kind = tvb(5, 1):uint()
  tree:add(f.version, tvb(4, 1))
  tree:add(f.type, tvb(5, 1))
  local flags_item = tree:add_le(f.flags, tvb(6, 2))
  flags_item:add_le(f.sealed, tvb(6, 2))
  flags_item:add_le(f.tagged, tvb(6, 2))
  tree:add_le(f.token, tvb(8, 8))
  tree:add_le(f.sequence, tvb(16, 4))
  local name = types[kind] or ("type " .. kind)
  pinfo.cols.info = "DHR " .. name
  if version ~= 3 then
    tree:add_proto_expert_info(e_version, "version " .. version)
    return true
  end
  if types[kind] == nil then
    malformed(tree, tvb, "unknown message type " .. kind)
    return true
  end
  if len > 1280 then malformed(tree, tvb, "longer than 1280 bytes") return true end
  local flags = tvb(6, 2):le_uint()
  if flags == 1 then
    if len < HEADER + SEAL_TAG then malformed(tree, tvb, "sealed datagram without room for its tag") return true end
    if len > HEADER + SEAL_TAG then tree:add(f.ciphertext, tvb(HEADER, len - HEADER - SEAL_TAG)) end
    tree:add(f.seal_tag, tvb(len - SEAL_TAG, SEAL_TAG))
    pinfo.cols.info = "DHR " .. name .. " (sealed)"
    return true
  end
  local body_len = len
  if flags == 2 then
    if len < HEADER + HS_TRAILER then malformed(tree, tvb, "handshake tag missing") return true end
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
