"""Copies of a suite's scenes with one change each (gen_optics.py, gen_gain.py): every SRC_DIR/*.json
scene that edit(scene, name) accepts, edited in place by it, written to DST_DIR under the name it
returns, with mesh paths rewritten to stay valid from DST_DIR (write_scene, which gen_family.py
uses too)."""
import json
import os


def copy_suite(src, dst, edit):
    """edit(scene, name) changes the scene (a dict) and returns the output file name, or None to
    skip the scene"""
    os.makedirs(dst, exist_ok=True)
    for name in sorted(os.listdir(src)):
        if not name.endswith(".json"):
            continue
        with open(os.path.join(src, name)) as f:
            scene = json.load(f)
        out = edit(scene, name)
        if out is None:
            continue
        write_scene(scene, src, dst, out)


def write_scene(scene, src, dst, name):
    """Writes scene (a dict read from directory src) as dst/name, its mesh paths rewritten to stay
    valid from dst; through a temporary file renamed into place"""
    for obj in scene.get("objects", []):
        if "file" in obj:
            obj["file"] = os.path.relpath(os.path.join(src, obj["file"]), dst)
    path = os.path.join(dst, name)
    with open(path + ".tmp", "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")
    os.replace(path + ".tmp", path)
