#!/usr/bin/env python3
"""Writes assets/scenes/courtyard.gltf: a small glTF 2.0 scene with a node hierarchy, one box
mesh shared by many nodes, a ground large enough to be chunked, and base colours. The buffer
is embedded as a data URI so the file stands alone."""
import base64, json, math, struct, pathlib

def box(hx, hy, hz):
    faces = [((1,0,0),(0,0,1),(0,1,0)), ((-1,0,0),(0,1,0),(0,0,1)), ((0,1,0),(0,0,1),(1,0,0)),
             ((0,-1,0),(1,0,0),(0,0,1)), ((0,0,1),(0,1,0),(1,0,0)), ((0,0,-1),(1,0,0),(0,1,0))]
    pos, nrm, idx = [], [], []
    for n, a, b in faces:
        cross = (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
        if sum(c*m for c, m in zip(cross, n)) < 0:
            a, b = b, a
        base = len(pos)
        for sa, sb in [(-1,-1),(1,-1),(1,1),(-1,1)]:
            p = [(n[k] + a[k]*sa + b[k]*sb) * (hx, hy, hz)[k] for k in range(3)]
            pos.append(p); nrm.append(list(n))
        idx += [base, base+1, base+2, base, base+2, base+3]
    return pos, nrm, idx

def grid(half, cells):
    pos, nrm, idx = [], [], []
    step = 2*half/cells
    for j in range(cells+1):
        for i in range(cells+1):
            pos.append([-half+i*step, 0.0, -half+j*step]); nrm.append([0.0, 1.0, 0.0])
    for j in range(cells):
        for i in range(cells):
            a = j*(cells+1)+i; b = a+1; c = a+cells+1; d = c+1
            idx += [a, c, b, b, c, d]
    return pos, nrm, idx

meshes_src = {"ground": grid(60.0, 40), "box": box(0.5, 0.5, 0.5)}
blob = bytearray(); views = []; accessors = []; meshes = []
def add_view(data, target):
    while len(blob) % 4: blob.append(0)
    views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
    blob.extend(data); return len(views)-1
for name, (pos, nrm, idx) in meshes_src.items():
    pv = add_view(b"".join(struct.pack("<3f", *p) for p in pos), 34962)
    nv = add_view(b"".join(struct.pack("<3f", *n) for n in nrm), 34962)
    iv = add_view(b"".join(struct.pack("<I", i) for i in idx), 34963)
    lo = [min(p[k] for p in pos) for k in range(3)]; hi = [max(p[k] for p in pos) for k in range(3)]
    accessors += [{"bufferView": pv, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
                  {"bufferView": nv, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
                  {"bufferView": iv, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]
    a = len(accessors)-3
    meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": a, "NORMAL": a+1}, "indices": a+2,
                   "material": 0 if name == "ground" else 1}]})
materials = [{"name": "stone", "pbrMetallicRoughness": {"baseColorFactor": [0.55, 0.52, 0.48, 1.0]}},
             {"name": "brick", "pbrMetallicRoughness": {"baseColorFactor": [0.60, 0.25, 0.18, 1.0]}}]
nodes = [{"name": "ground", "mesh": 0}]
# A colonnade: a parent node rotated and moved, pillars as children sharing the box mesh.
children = []
for k in range(8):
    angle = k / 8 * 2 * math.pi
    nodes.append({"name": f"pillar_{k}", "mesh": 1, "translation": [math.cos(angle)*12, 4.0, math.sin(angle)*12], "scale": [1.5, 8.0, 1.5]})
    children.append(len(nodes)-1)
nodes.append({"name": "colonnade", "children": children, "translation": [5.0, 0.0, -5.0],
              "rotation": [0.0, math.sin(0.2), 0.0, math.cos(0.2)]})
nodes.append({"name": "roof_ring", "mesh": 1, "translation": [5.0, 8.5, -5.0], "scale": [26.0, 1.0, 26.0]})
nodes.append({"name": "tower", "mesh": 1, "translation": [-30.0, 15.0, 25.0], "scale": [6.0, 30.0, 6.0]})
doc = {"asset": {"version": "2.0", "generator": "shadowlab scripts/make_courtyard.py"},
       "scene": 0, "scenes": [{"name": "courtyard", "nodes": [0, len(nodes)-3, len(nodes)-2, len(nodes)-1]}],
       "nodes": nodes, "meshes": meshes, "materials": materials, "accessors": accessors, "bufferViews": views,
       "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]}
out = pathlib.Path(__file__).resolve().parent.parent / "assets" / "scenes" / "courtyard.gltf"
out.write_text(json.dumps(doc, indent=1))
print(out, len(blob), "bytes of buffer")
