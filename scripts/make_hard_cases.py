#!/usr/bin/env python3
"""Writes the measure's hard-case scenes into assets/scenes/ (glTF 2.0, buffer embedded as a data
URI so each file stands alone). Each mesh is a union of axis-aligned boxes, every box closed
and wound counter-clockwise seen from outside.

- wall.gltf: a ground slab (-10,-0.1,-10)-(10,0,10) and a wall box (-0.16,0,-4)-(0.14,4,4), whose
  lit face is the plane x = 0.14, a short distance from a coordinate plane (issue 47, 1).
- house.gltf: a closed house of one mesh (a floor, four walls 0.2 m thick with a door gap, a
  roof: the shell of the box (-6,0,-4)-(6,5,4)) on an 18 m ground (issue 47, 4).

Run: python3 scripts/make_hard_cases.py"""
import base64, json, pathlib, struct

FACES = [((1, 0, 0), (0, 0, 1), (0, 1, 0)), ((-1, 0, 0), (0, 1, 0), (0, 0, 1)),
         ((0, 1, 0), (0, 0, 1), (1, 0, 0)), ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
         ((0, 0, 1), (0, 1, 0), (1, 0, 0)), ((0, 0, -1), (1, 0, 0), (0, 1, 0))]


def boxes_mesh(boxes):
    """One mesh of closed boxes, each given as (min, max)."""
    pos, nrm, idx = [], [], []
    for lo, hi in boxes:
        centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
        half = [(hi[k] - lo[k]) / 2 for k in range(3)]
        for n, a, b in FACES:
            cross = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
            if sum(c * m for c, m in zip(cross, n)) < 0:
                a, b = b, a
            base = len(pos)
            for sa, sb in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                pos.append([centre[k] + (n[k] + a[k] * sa + b[k] * sb) * half[k] for k in range(3)])
                nrm.append(list(n))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nrm, idx


def write(name, meshes_src, sun):
    blob = bytearray(); views = []; accessors = []; meshes = []; nodes = []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for mesh_name, boxes in meshes_src:
        pos, nrm, idx = boxes_mesh(boxes)
        pv = add_view(b"".join(struct.pack("<3f", *p) for p in pos), 34962)
        nv = add_view(b"".join(struct.pack("<3f", *n) for n in nrm), 34962)
        iv = add_view(b"".join(struct.pack("<I", i) for i in idx), 34963)
        lo = [min(p[k] for p in pos) for k in range(3)]
        hi = [max(p[k] for p in pos) for k in range(3)]
        accessors += [{"bufferView": pv, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": nv, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
                      {"bufferView": iv, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]
        a = len(accessors) - 3
        meshes.append({"name": mesh_name, "primitives": [{"attributes": {"POSITION": a, "NORMAL": a + 1}, "indices": a + 2}]})
        nodes.append({"name": mesh_name, "mesh": len(meshes) - 1})
    # The sun: a directional light shines down its node's -Z; this node turns -Z to -sun.
    nodes.append({"name": "sun", "rotation": sun_rotation(sun), "extensions": {"KHR_lights_punctual": {"light": 0}}})
    doc = {"asset": {"version": "2.0", "generator": "shadowlab scripts/make_hard_cases.py"},
           "extensionsUsed": ["KHR_lights_punctual"],
           "extensions": {"KHR_lights_punctual": {"lights": [{"name": "sun", "type": "directional", "intensity": 3.0}]}},
           "scene": 0, "scenes": [{"name": name, "nodes": list(range(len(nodes)))}],
           "nodes": nodes, "meshes": meshes, "accessors": accessors, "bufferViews": views,
           "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]}
    out = pathlib.Path(__file__).resolve().parent.parent / "assets" / "scenes" / f"{name}.gltf"
    out.write_text(json.dumps(doc, indent=1) + "\n")
    print(out, len(blob), "bytes of buffer")


def sun_rotation(to_sun):
    """The unit quaternion (x, y, z, w) turning -Z onto -to_sun (the light's direction)."""
    import math
    length = math.sqrt(sum(c * c for c in to_sun))
    d = [-c / length for c in to_sun]  # where the light shines
    f = [0.0, 0.0, -1.0]
    axis = [f[1] * d[2] - f[2] * d[1], f[2] * d[0] - f[0] * d[2], f[0] * d[1] - f[1] * d[0]]
    w = 1.0 + sum(a * b for a, b in zip(f, d))
    q = axis + [w]
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


GROUND_WALL = ((-10, -0.1, -10), (10, 0, 10))
write("wall", [("ground", [GROUND_WALL]), ("wall", [((-0.16, 0, -4), (0.14, 4, 4))])], (0.8, 0.5, 0.3))

T = 0.2  # wall thickness, m
DOOR = 0.5  # half the door's width, m
house = [
    ((-6, 0, -4), (6, T, 4)),  # floor
    ((-6, 5 - T, -4), (6, 5, 4)),  # roof
    ((-6, T, -4), (-6 + T, 5 - T, 4)),  # west wall
    ((6 - T, T, -4), (6, 5 - T, 4)),  # east wall
    ((-6 + T, T, -4), (6 - T, 5 - T, -4 + T)),  # north wall
    ((-6 + T, T, 4 - T), (-DOOR, 5 - T, 4)),  # south wall, west of the door
    ((DOOR, T, 4 - T), (6 - T, 5 - T, 4)),  # south wall, east of the door
    ((-DOOR, 2.2, 4 - T), (DOOR, 5 - T, 4)),  # over the door
]
write("house", [("ground", [((-9, -0.1, -9), (9, 0, 9))]), ("house", house)], (0.5, 0.8, 0.3))
