#!/usr/bin/env python3
"""Writes everything.tmj (a Tiled map with every object kind, property type, layer kind,
encoding and compression the loader reads), the hostile layer-data maps bad_layer_*.tmj,
and the fuzz seed fuzz/corpus/tiled/compressed_properties.tmj. Run from the repository
root:

    python3 tests/data/tiled/make_everything.py

The output is deterministic (gzip's time stamp is 0), so running it again changes
nothing. tests/test_tiled.c asserts what the loader makes of these files."""
import base64
import gzip
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
FLIP_H = 0x80000000

# 6 x 4 tiles, top row first; gid 1 a box, 2 a one-way half tile, 3 empty; the last
# ground tile flipped horizontally.
WIDTH, HEIGHT = 6, 4
GIDS = [0, 0, 0, 0, 0, 0,
        0, 0, 0, 2, 2, 0,
        0, 0, 0, 0, 0, 3,
        1, 1, 1, 1, 1, 1 | FLIP_H]


def raw(gids):
    return struct.pack("<%dI" % len(gids), *gids)


def b64(data):
    return base64.b64encode(data).decode("ascii")


def gz(data):
    return gzip.compress(data, mtime=0)


def prop(name, kind, value, **extra):
    p = {"name": name, "type": kind, "value": value}
    p.update(extra)
    return p


def tile_layer(ident, name, data, encoding=None, compression=None, properties=None):
    layer = {"id": ident, "name": name, "type": "tilelayer", "width": WIDTH, "height": HEIGHT, "x": 0, "y": 0,
             "opacity": 1, "visible": True, "data": data}
    if encoding:
        layer["encoding"] = encoding
    if compression:
        layer["compression"] = compression
    if properties:
        layer["properties"] = properties
    return layer


def obj(ident, name, x, y, w=0, h=0, cls=None, old_type=None, **extra):
    o = {"id": ident, "name": name, "x": x, "y": y, "width": w, "height": h, "rotation": 0, "visible": True}
    if cls is not None:
        o["class"] = cls
    if old_type is not None:
        o["type"] = old_type
    o.update(extra)
    return o


def tileset():
    box = {"id": 0, "objectgroup": {"type": "objectgroup", "name": "", "objects": [
        {"id": 1, "x": 0, "y": 0, "width": 16, "height": 16, "rotation": 0}]}}
    half = {"id": 1, "objectgroup": {"type": "objectgroup", "name": "", "objects": [
        {"id": 1, "x": 0, "y": 0, "width": 16, "height": 8, "rotation": 0}]},
        "properties": [prop("one_way", "bool", True)]}
    return {"firstgid": 1, "name": "terrain", "tilewidth": 16, "tileheight": 16, "tilecount": 4, "columns": 2,
            "image": "terrain.png", "imagewidth": 32, "imageheight": 32, "margin": 0, "spacing": 0,
            "tiles": [box, half]}


def bodies_layer():
    crate_props = [
        prop("label", "string", "wooden crate"),
        prop("hp", "int", -7),
        prop("weight", "float", 2.75),
        prop("breakable", "bool", True),
        prop("tint", "color", "#80ff8000"),
        prop("sound", "file", "sounds/crack.wav"),
        prop("target", "object", 2),
        prop("loot", "class", {"coins": 12, "chance": 0.25, "item": "key", "rare": False,
                               "bonus": {"gems": 1}}, propertytype="Loot"),
        prop("friction", "float", 0.25),
    ]
    objects = [
        obj(1, "crate", 16, 16, 16, 16, cls="Crate", properties=crate_props),
        obj(2, "ball", 48, 0, 16, 16, old_type="Ball", ellipse=True,
            properties=[prop("sensor", "bool", True)]),
        obj(3, "", 0, 32, polygon=[{"x": 0, "y": 0}, {"x": 16, "y": 0}, {"x": 0, "y": 16}]),
        obj(4, "ledge", 16, 40, polyline=[{"x": 0, "y": 0}, {"x": 32, "y": 0}]),
        obj(5, "spawn", 8, 40, cls="Spawn", point=True,
            properties=[prop("team", "string", "red"), prop("facing", "int", 1)]),
        obj(6, "caption", 0, 0, 64, 16, text={"text": "Hello", "wrap": True}),
    ]
    return {"id": 20, "name": "bodies", "type": "objectgroup", "draworder": "topdown", "opacity": 1,
            "visible": True, "x": 0, "y": 0, "objects": objects,
            "properties": [prop("type", "string", "static"), prop("layer_tag", "string", "solid")]}


def markers_layer():
    objects = [
        obj(10, "checkpoint", 40, 24, point=True),
        obj(11, "goal", 64, 16, 32, 16, cls="Trigger",
            properties=[prop("message", "string", "well done"), prop("delay", "float", 1.5)]),
        obj(12, "zone", 32, 0, 16, 32, ellipse=True, rotation=90),
        obj(13, "area", 48, 8, polygon=[{"x": 0, "y": 0}, {"x": 8, "y": 0}, {"x": 0, "y": 8}]),
        obj(14, "path", 0, 8, polyline=[{"x": 0, "y": 0}, {"x": 16, "y": 8}]),
        obj(15, "coin", 80, 64, 16, 16, cls="Pickup", gid=1),
        obj(16, "", 0, 0, 32, 16, text={"text": "markers"}),
    ]
    return {"id": 30, "name": "markers", "type": "objectgroup", "draworder": "topdown", "opacity": 1,
            "visible": False, "x": 0, "y": 0, "objects": objects,
            "properties": [prop("physics", "bool", False), prop("purpose", "string", "triggers")]}


def everything():
    data = raw(GIDS)
    tiles = [
        tile_layer(2, "csv", GIDS, encoding="csv", properties=[prop("depth", "int", 2)]),
        tile_layer(3, "base64", b64(data), encoding="base64"),
        tile_layer(4, "zlib", b64(zlib.compress(data, 9)), encoding="base64", compression="zlib"),
        {"id": 5, "name": "deeper", "type": "group", "opacity": 1, "visible": True, "x": 0, "y": 0,
         "layers": [tile_layer(6, "gzip", b64(gz(data)), encoding="base64", compression="gzip")]},
    ]
    terrain = {"id": 1, "name": "terrain", "type": "group", "opacity": 1, "visible": True, "x": 0, "y": 0,
               "layers": tiles, "properties": [prop("theme", "string", "cave")]}
    image = {"id": 40, "name": "sky", "type": "imagelayer", "image": "sky.png", "opacity": 1, "visible": True,
             "x": 0, "y": 0}
    map_props = [
        prop("title", "string", "Everything"),
        prop("level", "int", 3),
        prop("gravity_scale", "float", 0.5),
        prop("night", "bool", False),
        prop("sky", "color", "#336699"),
        prop("music", "file", "music/theme.ogg"),
        prop("boss", "object", 0),
        prop("friction", "float", 0.5),
    ]
    return {"type": "map", "version": "1.10", "tiledversion": "1.10.2", "orientation": "orthogonal",
            "renderorder": "right-down", "infinite": False, "width": WIDTH, "height": HEIGHT,
            "tilewidth": 16, "tileheight": 16, "nextlayerid": 41, "nextobjectid": 17,
            "properties": map_props, "tilesets": [tileset()],
            "layers": [terrain, bodies_layer(), markers_layer(), image]}


def small_map(layer):
    """A 4 x 2 map (32 bytes of layer data) with one tile layer and an empty tileset."""
    return {"type": "map", "tiledversion": "1.10.2", "orientation": "orthogonal", "infinite": False,
            "width": 4, "height": 2, "tilewidth": 16, "tileheight": 16,
            "tilesets": [{"firstgid": 1, "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 1}],
            "layers": [layer]}


def small_layer(data, compression, encoding="base64"):
    layer = {"id": 1, "name": "ground", "type": "tilelayer", "width": 4, "height": 2, "x": 0, "y": 0,
             "encoding": encoding, "compression": compression, "data": data}
    return small_map(layer)


def hostile():
    exact = raw([1] * 8)
    z = zlib.compress(exact, 9)
    g = gz(exact)
    return {
        # 1 MiB of zeros: about 1 KiB compressed, 32768 times what the layer holds
        "bad_layer_zlib_bomb.tmj": small_layer(b64(zlib.compress(bytes(1 << 20), 9)), "zlib"),
        "bad_layer_zlib_truncated.tmj": small_layer(b64(z[: len(z) // 2]), "zlib"),
        "bad_layer_zlib_short.tmj": small_layer(b64(zlib.compress(exact[:16], 9)), "zlib"),
        "bad_layer_zlib_trailing.tmj": small_layer(b64(z + b"junk"), "zlib"),
        "bad_layer_zlib_garbage.tmj": small_layer(b64(bytes(range(7, 47))), "zlib"),
        # all 32 bytes there, the CRC and length trailer cut off
        "bad_layer_gzip_no_trailer.tmj": small_layer(b64(g[:-8]), "gzip"),
        "bad_layer_gzip_bad_base64.tmj": small_layer("H4sI!!!!" + b64(g)[8:], "gzip"),
        "bad_layer_zstd.tmj": small_layer("KLUv/SAgAQAA", "zstd"),
        "bad_layer_csv_compressed.tmj": small_layer([1] * 8, "zlib", encoding="csv"),
    }


def fuzz_seed():
    data = raw([1, 0, 1, 0, 1, 1, 1, 1])
    seed = small_map({"id": 1, "name": "z", "type": "tilelayer", "width": 4, "height": 2, "x": 0, "y": 0,
                      "encoding": "base64", "compression": "zlib", "data": b64(zlib.compress(data, 9))})
    seed["layers"].append({"id": 2, "name": "g", "type": "tilelayer", "width": 4, "height": 2, "x": 0, "y": 0,
                           "encoding": "base64", "compression": "gzip", "data": b64(gz(data))})
    seed["layers"].append({"id": 3, "name": "m", "type": "objectgroup", "objects": [
        obj(1, "spawn", 8, 8, point=True, properties=[prop("c", "color", "#ff00ff00")]),
        obj(2, "r", 0, 0, 16, 16, cls="K", properties=[prop("k", "class", {"a": 1, "b": {"c": "d"}})])],
        "properties": [prop("physics", "bool", False), prop("f", "file", "x.png")]})
    seed["properties"] = [prop("n", "int", 5), prop("o", "object", 1)]
    return seed


def write(path, document):
    with open(path, "w") as f:
        json.dump(document, f, indent=1)
        f.write("\n")


def main():
    write(os.path.join(HERE, "everything.tmj"), everything())
    for name, document in hostile().items():
        write(os.path.join(HERE, name), document)
    write(os.path.join(ROOT, "fuzz", "corpus", "tiled", "compressed_properties.tmj"), fuzz_seed())


if __name__ == "__main__":
    main()
