#!/usr/bin/env python3
"""Generates the project's own default scene: assets/scenes/default_room.gltf (+ .cameras.json), and its sibling
default_room_area.gltf (+ .cameras.json): the same room whose lights have an extent (an EXT_lights_area rect panel,
a sphere light), so soft-shadow code runs without the shared test data.

A 4 x 3 m room, 3 m high (floor at y = 0, walls at x = +-2 and z = -1.5, open towards +z and above),
single-sided and facing inward, with objects that cast clear shadows: two boxes, a shelf plank on the
left wall, a column and a low-poly sphere, lit by three KHR_lights_punctual point lights. The floor has
a procedural checker texture (PNG written with zlib). Standard library only; the output is
deterministic, so re-running it reproduces the committed files byte for byte.

Usage: scripts/make_default_scene.py [output_dir]   (default: assets/scenes next to this script's repo)
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

ROOM_X = 2.0    # walls at x = -2 and +2
ROOM_Z = 1.5    # back wall at z = -1.5; the room is open at z = +1.5
ROOM_H = 3.0
EYE_HEIGHT = 1.6


class Mesh:
    """Triangle list with per-vertex normals and texture coordinates (local space)."""

    def __init__(self):
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def vertex(self, p, n, uv=(0.0, 0.0)):
        self.positions.append(tuple(float(v) for v in p))
        self.normals.append(tuple(float(v) for v in n))
        self.uvs.append(tuple(float(v) for v in uv))
        return len(self.positions) - 1

    def quad(self, a, b, c, d, n, uvs=((0, 0), (1, 0), (1, 1), (0, 1))):
        """Counter-clockwise a, b, c, d seen from the side the normal points to."""
        i = [self.vertex(p, n, uv) for p, uv in zip((a, b, c, d), uvs)]
        self.indices += [i[0], i[1], i[2], i[0], i[2], i[3]]


def unit_box():
    """Unit cube from (-0.5, 0, -0.5) to (0.5, 1, 0.5): resting on y = 0, outward faces."""
    m = Mesh()
    x0, x1, y0, y1, z0, z1 = -0.5, 0.5, 0.0, 1.0, -0.5, 0.5
    m.quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (0, 0, 1))    # +z
    m.quad((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (0, 0, -1))   # -z
    m.quad((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (1, 0, 0))    # +x
    m.quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (-1, 0, 0))   # -x
    m.quad((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0), (0, 1, 0))    # top
    m.quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), (0, -1, 0))   # bottom
    return m


def cylinder(radius, height, segments):
    """Capped cylinder standing on y = 0 around the y axis; smooth sides, flat caps."""
    m = Mesh()
    for s in range(segments):
        a0 = 2 * math.pi * s / segments
        a1 = 2 * math.pi * (s + 1) / segments
        c0, s0, c1, s1 = math.cos(a0), math.sin(a0), math.cos(a1), math.sin(a1)
        # Side quad, counter-clockwise from outside (angle grows from +x towards -z).
        p = [(radius * c0, 0, -radius * s0), (radius * c1, 0, -radius * s1),
             (radius * c1, height, -radius * s1), (radius * c0, height, -radius * s0)]
        n = [(c0, 0, -s0), (c1, 0, -s1), (c1, 0, -s1), (c0, 0, -s0)]
        i = [m.vertex(p[k], n[k]) for k in range(4)]
        m.indices += [i[0], i[1], i[2], i[0], i[2], i[3]]
        top = [m.vertex((0, height, 0), (0, 1, 0)), m.vertex(p[3], (0, 1, 0)), m.vertex(p[2], (0, 1, 0))]
        m.indices += top
        bottom = [m.vertex((0, 0, 0), (0, -1, 0)), m.vertex(p[1], (0, -1, 0)), m.vertex(p[0], (0, -1, 0))]
        m.indices += bottom
    return m


def uv_sphere(radius, segments, rings):
    """Smooth sphere centred at the origin."""
    m = Mesh()
    rows = []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        row = []
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            row.append(m.vertex(tuple(radius * v for v in n), n, (s / segments, r / rings)))
        rows.append(row)
    for r in range(rings):
        for s in range(segments):
            a, b = rows[r][s], rows[r][s + 1]
            c, d = rows[r + 1][s + 1], rows[r + 1][s]
            if r != rings - 1:  # the last ring's c and d are both the south pole
                m.indices += [a, d, c]
            if r != 0:  # the first ring's a and b are both the north pole
                m.indices += [a, c, b]
    return m


def room():
    """Floor and three walls, facing inward. The floor's UVs tile the checker every 0.5 m."""
    floor, walls = Mesh(), Mesh()
    x0, x1, z0, z1, h = -ROOM_X, ROOM_X, -ROOM_Z, ROOM_Z, ROOM_H
    tu, tv = 2 * ROOM_X / 0.5 / 8, 2 * ROOM_Z / 0.5 / 8  # the texture holds 8 x 8 squares
    floor.quad((x0, 0, z1), (x1, 0, z1), (x1, 0, z0), (x0, 0, z0), (0, 1, 0),
               ((0, tv), (tu, tv), (tu, 0), (0, 0)))
    walls.quad((x0, 0, z0), (x1, 0, z0), (x1, h, z0), (x0, h, z0), (0, 0, 1))   # back wall, faces +z
    walls.quad((x0, 0, z1), (x0, 0, z0), (x0, h, z0), (x0, h, z1), (1, 0, 0))   # left wall, faces +x
    walls.quad((x1, 0, z0), (x1, 0, z1), (x1, h, z1), (x1, h, z0), (-1, 0, 0))  # right wall, faces -x
    return floor, walls


def checker_png(size=64, squares=8):
    """RGB PNG checkerboard in two warm greys (sRGB)."""
    light, dark = (200, 190, 172), (120, 112, 100)
    cell = size // squares
    raw = bytearray()
    for y in range(size):
        raw.append(0)  # filter: none
        for x in range(size):
            raw += bytes(light if ((x // cell) + (y // cell)) % 2 == 0 else dark)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) +
            chunk(b"IEND", b""))


class Writer:
    """Packs meshes into one binary buffer and the glTF JSON that describes it."""

    def __init__(self):
        self.blob = bytearray()
        self.gltf = {"asset": {"version": "2.0", "generator": "DHR-XR scripts/make_default_scene.py",
                               "copyright": "DHR-XR project (generated)"},
                     "extensionsUsed": ["KHR_lights_punctual"],
                     "scene": 0, "scenes": [{"name": "default_room", "nodes": []}],
                     "nodes": [], "meshes": [], "materials": [], "accessors": [], "bufferViews": [],
                     "buffers": [], "images": [], "textures": [], "samplers": []}

    def view(self, data, target=None):
        while len(self.blob) % 4:
            self.blob.append(0)
        v = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.blob += data
        self.gltf["bufferViews"].append(v)
        return len(self.gltf["bufferViews"]) - 1

    def accessor(self, values, kind, count, component=5126, bounds=False):
        fmt = "<%d%s" % (len(values), "f" if component == 5126 else ("H" if component == 5123 else "I"))
        target = 34963 if kind == "SCALAR" else 34962
        a = {"bufferView": self.view(struct.pack(fmt, *values), target), "componentType": component,
             "count": count, "type": kind}
        if bounds:
            n = 3
            a["min"] = [min(values[i::n]) for i in range(n)]
            a["max"] = [max(values[i::n]) for i in range(n)]
        self.gltf["accessors"].append(a)
        return len(self.gltf["accessors"]) - 1

    def geometry(self, m):
        """Accessors of a mesh, shareable between several glTF meshes (different materials)."""
        flat = lambda rows: [round(v, 6) for row in rows for v in row]
        big = len(m.positions) > 65535
        return {"POSITION": self.accessor(flat(m.positions), "VEC3", len(m.positions), bounds=True),
                "NORMAL": self.accessor(flat(m.normals), "VEC3", len(m.normals)),
                "TEXCOORD_0": self.accessor(flat(m.uvs), "VEC2", len(m.uvs)),
                "indices": self.accessor(m.indices, "SCALAR", len(m.indices), 5125 if big else 5123)}

    def material(self, name, rgba, texture=None):
        pbr = {"baseColorFactor": list(rgba), "metallicFactor": 0.0, "roughnessFactor": 0.9}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        self.gltf["materials"].append({"name": name, "pbrMetallicRoughness": pbr})
        return len(self.gltf["materials"]) - 1

    def mesh(self, name, geometry, material):
        attributes = {k: v for k, v in geometry.items() if k != "indices"}
        self.gltf["meshes"].append({"name": name, "primitives": [
            {"attributes": attributes, "indices": geometry["indices"], "material": material}]})
        return len(self.gltf["meshes"]) - 1

    def node(self, name, mesh=None, translation=None, rotation_y_deg=None, scale=None, light=None, rotation=None,
             area_light=None):
        n = {"name": name}
        if mesh is not None:
            n["mesh"] = mesh
        if translation:
            n["translation"] = [round(v, 6) for v in translation]
        if rotation_y_deg:
            half = math.radians(rotation_y_deg) / 2
            n["rotation"] = [0.0, round(math.sin(half), 9), 0.0, round(math.cos(half), 9)]
        if rotation:
            n["rotation"] = [round(v, 9) for v in rotation]
        if scale:
            n["scale"] = list(scale)
        if light is not None:
            n["extensions"] = {"KHR_lights_punctual": {"light": light}}
        if area_light is not None:
            n["extensions"] = {"EXT_lights_area": {"light": area_light}}
        self.gltf["nodes"].append(n)
        index = len(self.gltf["nodes"]) - 1
        self.gltf["scenes"][0]["nodes"].append(index)
        return index

    def finish(self):
        while len(self.blob) % 4:
            self.blob.append(0)
        uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.blob)).decode("ascii")
        self.gltf["buffers"].append({"byteLength": len(self.blob), "uri": uri})
        return self.gltf


def build(area=False):
    """The default room; area=True: its sibling whose lights have an extent (default_room_area.gltf)."""
    w = Writer()
    png = checker_png()
    w.gltf["images"].append({"name": "floor_checker", "mimeType": "image/png", "bufferView": w.view(png)})
    w.gltf["samplers"].append({"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497})
    w.gltf["textures"].append({"sampler": 0, "source": 0})

    floor_mat = w.material("floor_checker", (1.0, 1.0, 1.0, 1.0), texture=0)
    wall_mat = w.material("wall_offwhite", (0.82, 0.8, 0.76, 1.0))
    red = w.material("box_red", (0.75, 0.18, 0.12, 1.0))
    blue = w.material("box_blue", (0.15, 0.3, 0.7, 1.0))
    wood = w.material("shelf_wood", (0.55, 0.38, 0.22, 1.0))
    grey = w.material("column_grey", (0.6, 0.6, 0.62, 1.0))
    yellow = w.material("sphere_yellow", (0.85, 0.7, 0.15, 1.0))

    floor, walls = room()
    box = w.geometry(unit_box())  # one geometry, instanced by three nodes
    w.node("floor", w.mesh("floor", w.geometry(floor), floor_mat))
    w.node("walls", w.mesh("walls", w.geometry(walls), wall_mat))
    w.node("box_red", w.mesh("box_red", box, red), translation=(-0.9, 0.0, -0.5), rotation_y_deg=20,
           scale=(0.6, 0.6, 0.6))
    w.node("box_blue_tall", w.mesh("box_blue", box, blue), translation=(1.0, 0.0, -0.7), rotation_y_deg=-15,
           scale=(0.4, 1.2, 0.4))
    w.node("shelf", w.mesh("shelf", box, wood), translation=(-ROOM_X + 0.16, 1.5, -0.3), scale=(0.3, 0.04, 1.0))
    w.node("column", w.mesh("column", w.geometry(cylinder(0.15, 2.2, 32)), grey), translation=(0.15, 0.0, -1.05))
    w.node("sphere", w.mesh("sphere", w.geometry(uv_sphere(0.35, 24, 16)), yellow), translation=(-0.25, 0.35, 0.1))

    if area:
        add_area_lights(w)
        return w.finish()
    w.gltf["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"name": "ceiling_key", "type": "point", "color": [1.0, 0.93, 0.82], "intensity": 16.0},
        {"name": "fill_left", "type": "point", "color": [0.8, 0.88, 1.0], "intensity": 7.0},
        {"name": "lamp_right", "type": "point", "color": [1.0, 0.78, 0.5], "intensity": 2.0, "range": 6.0},
    ]}}
    w.node("light_ceiling_key", translation=(0.5, 2.7, 0.3), light=0)
    w.node("light_fill_left", translation=(-1.5, 2.0, 1.0), light=1)
    w.node("light_lamp_right", translation=(1.1, 0.9, 0.6), light=2)
    return w.finish()


def add_area_lights(w):
    """The same three light positions, with an extent: the ceiling key becomes a 0.8 x 0.4 m EXT_lights_area panel
    facing down (50 nits x 0.32 m^2 = 16 cd, as the point light it replaces), the lamp a 5 cm sphere light
    (extras.radius), the fill stays a point light."""
    w.gltf["extensionsUsed"] = ["KHR_lights_punctual", "EXT_lights_area"]
    w.gltf["extensions"] = {
        "KHR_lights_punctual": {"lights": [
            {"name": "fill_left", "type": "point", "color": [0.8, 0.88, 1.0], "intensity": 7.0},
            {"name": "lamp_right", "type": "point", "color": [1.0, 0.78, 0.5], "intensity": 2.0, "range": 6.0,
             "extras": {"radius": 0.05}},
        ]},
        "EXT_lights_area": {"lights": [
            {"name": "ceiling_panel", "type": "rect", "color": [1.0, 0.93, 0.82], "intensity": 50.0, "size": 0.4,
             "rect": {"aspect": 2.0}},
        ]},
    }
    s = math.sqrt(0.5)
    # -90 degrees about X: the node's -Z (the emitting side) points down.
    w.node("light_ceiling_panel", translation=(0.5, 2.7, 0.3), rotation=(-s, 0.0, 0.0, s), area_light=0)
    w.node("light_fill_left", translation=(-1.5, 2.0, 1.0), light=0)
    w.node("light_lamp_right", translation=(1.1, 0.9, 0.6), light=1)


def cameras(scene="default_room.gltf"):
    def cam(name, position, target):
        return {"name": name, "position": list(position), "target": list(target)}
    return {"scene": scene, "units": "metres", "up": [0, 1, 0], "yfov_deg_suggested": 60,
            "cameras": [cam("entrance_overview", (0.0, EYE_HEIGHT, 1.35), (-0.1, 0.5, -0.9)),
                        cam("left_corner", (-1.6, EYE_HEIGHT, 1.2), (0.6, 0.4, -0.8)),
                        cam("right_side_shelf", (1.6, EYE_HEIGHT, 0.9), (-1.4, 0.9, -0.4))]}


def write_json(path, value, **kwargs):
    with open(path, "w", encoding="ascii", newline="\n") as f:
        json.dump(value, f, **kwargs)
        f.write("\n")


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "assets", "scenes")
    os.makedirs(out_dir, exist_ok=True)
    for name, area in (("default_room", False), ("default_room_area", True)):
        gltf = build(area)
        path = os.path.join(out_dir, name + ".gltf")
        write_json(path, gltf, indent=1, separators=(",", ": "))
        write_json(os.path.join(out_dir, name + ".cameras.json"), cameras(name + ".gltf"), indent=2)
        triangles = sum(gltf["accessors"][p["indices"]]["count"] // 3
                        for n in gltf["nodes"] if "mesh" in n for p in gltf["meshes"][n["mesh"]]["primitives"])
        print("wrote %s (%d bytes, %d triangles drawn)" % (path, os.path.getsize(path), triangles))

if __name__ == "__main__":
    main()
