"""Gives every primitive of a GLB one material with a base colour and a normal texture (a
4 x 4 PNG made here), so that gltfpack quantises TEXCOORD_0 with KHR_texture_transform as it
does for textured models. Usage: python3 textured.py IN.glb OUT.gltf (OUT.bin and
texture.png are written beside OUT.gltf)."""
import json
import os
import struct
import sys
import zlib


def png(width, height, rgb):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    rows = b"".join(b"\0" + b"".join(bytes(rgb(x, y)) for x in range(width))
                    for y in range(height))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


source, target = sys.argv[1], sys.argv[2]
data = open(source, "rb").read()
json_length = struct.unpack_from("<I", data, 12)[0]
document = json.loads(data[20:20 + json_length])
binary = data[20 + json_length + 8:]
folder = os.path.dirname(target)
stem = os.path.splitext(os.path.basename(target))[0]
open(os.path.join(folder, stem + ".bin"), "wb").write(binary)
open(os.path.join(folder, "texture.png"), "wb").write(
    png(4, 4, lambda x, y: (128 + 20 * x, 128, 255 - 20 * y)))
document["buffers"][0]["uri"] = stem + ".bin"
document["images"] = [{"uri": "texture.png"}]
document["textures"] = [{"source": 0}]
document["materials"] = [{
    "name": "textured",
    "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
    "normalTexture": {"index": 0},
}]
for mesh in document["meshes"]:
    for primitive in mesh["primitives"]:
        primitive["material"] = 0
json.dump(document, open(target, "w"), indent=1)
