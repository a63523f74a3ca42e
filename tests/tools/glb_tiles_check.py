#!/usr/bin/env python3
"""glb_tiles_check.py DIR - read back every tile .glb that DIR/index.json lists and check
that the tiles join into one closed globe (docs/export.md, "Tiled planets").

For each file: the glTF binary's JSON and BIN chunks are parsed (the container format,
not our writer), its one primitive's POSITION and NORMAL floats are read, and the scene
extras must name the tile the index says. Then, over all tiles:
  - every vertex on a tile's border has an exactly equal position (same float bits) in
    another tile's file: tile seams inside a face, face seams and cube corners alike;
  - vertices with the same position have the same normal (bits);
  - the number of distinct positions is Euler's 6 M^2 + 2 for M quads per face edge, so
    no seam vertex is duplicated with a different position.
Prints the figures; exits 1 on a failed check."""
import json
import os
import struct
import sys
from collections import defaultdict


def read_glb(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and length == len(data), path
    jlen, jtype = struct.unpack_from("<II", data, 12)
    assert jtype == 0x4E4F534A, path
    doc = json.loads(data[20:20 + jlen])
    off = 20 + jlen
    blen, btype = struct.unpack_from("<II", data, off)
    assert btype == 0x004E4942, path
    return doc, data[off + 8:off + 8 + blen]


def floats(doc, binc, accessor, ncomp):
    acc = doc["accessors"][accessor]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    raw = binc[start:start + acc["count"] * ncomp * 4]
    return [raw[k * ncomp * 4:(k + 1) * ncomp * 4] for k in range(acc["count"])]


def main():
    d = sys.argv[1]
    with open(os.path.join(d, "index.json")) as f:
        index = json.load(f)
    tiles = index["tile_files"]
    ok = True
    normal_of = {}
    owners = defaultdict(set)
    border = []
    mesh_res = None
    for k, t in enumerate(tiles):
        if "glb" not in t:
            print(f"index.json: tile {k} lists no glb")
            return 1
        doc, binc = read_glb(os.path.join(d, t["glb"]))
        ex = doc["scenes"][0]["extras"]
        if (ex["tile_face"], ex["tile_x"], ex["tile_y"]) != (t["face"], t["tx"], t["ty"]):
            print(f"{t['glb']}: scene extras name tile {ex['tile_face']} {ex['tile_x']} "
                  f"{ex['tile_y']}")
            ok = False
        mesh_res = ex["mesh_res"]
        prims = doc["meshes"][0]["primitives"]
        if len(prims) != 1:
            print(f"{t['glb']}: {len(prims)} primitives")
            ok = False
        pos = floats(doc, binc, prims[0]["attributes"]["POSITION"], 3)
        nrm = floats(doc, binc, prims[0]["attributes"]["NORMAL"], 3)
        w = int(round(len(pos) ** 0.5))
        for v, p in enumerate(pos):
            owners[p].add(k)
            if p in normal_of and normal_of[p] != nrm[v]:
                ok = False
                print(f"{t['glb']}: vertex {v}: normal differs from another tile's")
            normal_of.setdefault(p, nrm[v])
            i, j = v % w, v // w
            if i in (0, w - 1) or j in (0, w - 1):
                border.append((k, v, p))
    lonely = [(k, v) for k, v, p in border if len(owners[p]) < 2]
    expected = 6 * mesh_res * mesh_res + 2
    worst = 0.0
    if lonely:  # how far the unmatched border vertices lie from the nearest other tile's
        allp = [(struct.unpack("<3f", p), ks) for p, ks in owners.items()]
        for k, v, p in border[:2000]:
            if len(owners[p]) >= 2:
                continue
            a = struct.unpack("<3f", p)
            best = min(max(abs(a[c] - b[c]) for c in range(3)) for b, ks in allp if k not in ks)
            worst = max(worst, best)
    print(f"tiles {len(tiles)}, mesh_res {mesh_res}, distinct positions {len(owners)} "
          f"(Euler {expected}), border vertices {len(border)}, unmatched {len(lonely)}, "
          f"largest gap of an unmatched one {worst:g} m")
    if lonely or len(owners) != expected:
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
