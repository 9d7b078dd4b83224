"""Makes a VRM 0.x avatar for the page's checks: Fox.glb (skinned, CC-BY 4.0, see
assets/models/licenses) with VRM 0.x's root extension `VRM` (a humanoid naming two of its
joints), written as a .vrm. Usage: python3 vrm.py IN.glb OUT.vrm"""
import json
import struct
import sys

source, target = sys.argv[1:]
data = open(source, "rb").read()
magic, version, _ = struct.unpack_from("<4sII", data, 0)
assert magic == b"glTF" and version == 2, "not a GLB"
length, kind = struct.unpack_from("<I4s", data, 12)
assert kind == b"JSON"
document = json.loads(data[20:20 + length])
rest = data[20 + length:]
document["extensionsUsed"] = sorted(set(document.get("extensionsUsed", [])) | {"VRM"})
document.setdefault("extensions", {})["VRM"] = {
    "exporterVersion": "seamlit web check",
    "specVersion": "0.0",
    "meta": {"title": "Fox as a VRM 0.x avatar", "author": "PixelMannen (model), seamlit (VRM extension)"},
    "humanoid": {"humanBones": [{"bone": "hips", "node": 0}, {"bone": "head", "node": 1}]},
}
text = json.dumps(document, separators=(",", ":")).encode()
text += b" " * (-len(text) % 4)
body = struct.pack("<I4s", len(text), b"JSON") + text + rest
open(target, "wb").write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
