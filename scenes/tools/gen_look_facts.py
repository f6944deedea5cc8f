#!/usr/bin/env python3
"""Writes scenes/src/look/facts.rs: the visual facts of LIBERO's objects and fixtures.

For each catalog category it reads the asset XML (from a LIBERO asset tree given as the first
argument) and records every visual geom (group 1, or contype = conaffinity = 0): the body it
moves with (jointless sub-bodies fused into their parent, as the catalog does), its pose in that
body's frame, its shape (mesh file and scale, or a primitive), and its MuJoCo material (rgba,
specular, shininess, reflectance, emission, texture with type and texrepeat; `texuniform` is
checked to be off).
Only numbers and upstream file paths are written: no XML text.

It also records the scene XMLs' decor: every visual mesh geom of each scene's worldbody (the
kitchen's backdrop, the living room's and study's tables, shelves and paintings), posed in the
world frame; the floor, walls and box tables are drawn from the scene class.

It also records the visual geoms of robosuite's Panda and its gripper (robosuite 1.4.0's
`models/assets`), by the robot model's body names.

Usage: python3 scenes/tools/gen_look_facts.py <libero assets dir> <robosuite models/assets dir> > scenes/src/look/facts.rs
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

CATEGORIES = [
    ("akita_black_bowl", "stable_scanned_objects/akita_black_bowl/akita_black_bowl.xml"),
    ("plate", "stable_scanned_objects/plate/plate.xml"),
    ("glazed_rim_porcelain_ramekin", "stable_scanned_objects/glazed_rim_porcelain_ramekin/glazed_rim_porcelain_ramekin.xml"),
    ("basket", "stable_scanned_objects/basket/basket.xml"),
    ("chefmate_8_frypan", "stable_scanned_objects/chefmate_8_frypan/chefmate_8_frypan.xml"),
] + [
    (c, f"stable_hope_objects/{c}/{c}.xml")
    for c in ["cookies", "alphabet_soup", "tomato_sauce", "bbq_sauce", "butter", "chocolate_pudding",
              "cream_cheese", "ketchup", "salad_dressing", "milk", "orange_juice"]
] + [
    (c, f"turbosquid_objects/{c}/{c}.xml")
    for c in ["wine_bottle", "moka_pot", "porcelain_mug", "red_coffee_mug", "white_yellow_mug", "black_book"]
] + [
    (c, f"articulated_objects/{c}.xml") for c in ["wooden_cabinet", "white_cabinet", "flat_stove", "microwave"]
] + [
    ("wine_rack", "turbosquid_objects/wine_rack/wine_rack.xml"),
    ("desk_caddy", "turbosquid_objects/desk_caddy/desk_caddy.xml"),
]

GEOM_DEFAULT = {"type": "sphere", "pos": "0 0 0", "quat": "1 0 0 0", "size": "0 0 0", "rgba": "0.5 0.5 0.5 1",
                "group": "0", "contype": "1", "conaffinity": "1"}
MATERIAL_DEFAULT = {"rgba": "1 1 1 1", "specular": "0.5", "shininess": "0.5", "reflectance": "0", "emission": "0",
                    "texrepeat": "1 1", "texuniform": "false"}


def floats(s):
    return [float(x) for x in s.split()]


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return [w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2]


def qrot(q, v):
    p = qmul(qmul(q, [0.0] + list(v)), [q[0], -q[1], -q[2], -q[3]])
    return p[1:]


def qnorm(q):
    n = math.sqrt(sum(x * x for x in q))
    return [x / n for x in q]


def compose(parent, child):
    (pp, pq), (cp, cq) = parent, child
    r = qrot(pq, cp)
    return [pp[i] + r[i] for i in range(3)], qnorm(qmul(pq, cq))


def defaults_of(root):
    """Class name -> geom attribute defaults (nested classes inherit)."""
    out = {}

    def walk(node, inherited):
        for d in node.findall("default"):
            name = d.get("class", "main")
            attrs = dict(inherited)
            g = d.find("geom")
            if g is not None:
                attrs.update(g.attrib)
            out[name] = attrs
            walk(d, attrs)

    for top in root.findall("default"):
        attrs = {}
        g = top.find("geom")
        if g is not None:
            attrs.update(g.attrib)
        out[top.get("class", "main")] = attrs
        walk(top, attrs)
    return out


def fmt(xs):
    return "[" + ", ".join(repr(float(x)) for x in xs) + "]"


def parts_of(assets, rel, root_name, keep, meshes_only=False):
    """The visual parts under body `root_name` of `rel` (its worldbody for `None`); a body starts
    a new frame when `keep(body)`; with `meshes_only`, mesh geoms only."""
    path = os.path.join(assets, rel)
    root = ET.parse(path).getroot()
    base = os.path.dirname(rel)
    compiler = root.find("compiler")
    meshdir = compiler.get("meshdir", "") if compiler is not None else ""
    texdir = compiler.get("texturedir", "") if compiler is not None else ""
    norm = lambda d, f: os.path.normpath(os.path.join(base, d, f))
    textures, materials, meshes = {}, {}, {}
    for a in root.iter("asset"):
        for t in a.findall("texture"):
            textures.setdefault(t.get("name"), t)
        for m in a.findall("material"):
            materials.setdefault(m.get("name"), m)
        for m in a.findall("mesh"):
            meshes.setdefault(m.get("name"), m)
    classes = defaults_of(root)
    obj = root.find("worldbody") if root_name is None else next(b for b in root.iter("body") if b.get("name") == root_name)
    parts = []

    def visit(body, frame, owner, childclass):
        for g in body.findall("geom"):
            cls = g.get("class", childclass)
            attrs = dict(GEOM_DEFAULT)
            attrs.update(classes.get("main", {}))
            if cls:
                attrs.update(classes.get(cls, {}))
            attrs.update(g.attrib)
            visual = attrs["group"] == "1" or (attrs["contype"] == "0" and attrs["conaffinity"] == "0" and attrs["group"] != "0")
            if not visual or (meshes_only and attrs["type"] != "mesh"):
                continue
            pos, quat = compose(frame, (floats(attrs["pos"]), qnorm(floats(attrs["quat"]))))
            kind = attrs["type"]
            size = floats(attrs["size"])
            if kind == "mesh":
                m = meshes[attrs["mesh"]]
                scale = floats(m.get("scale", "1 1 1"))
                shape = f'Shape::Mesh {{ file: "{norm(meshdir, m.get("file"))}", scale: {fmt(scale)} }}'
            elif kind == "box":
                shape = f"Shape::Box {{ half: {fmt(size)} }}"
            elif kind == "capsule":
                shape = f"Shape::Capsule {{ radius: {float(size[0])!r}, half_height: {float(size[1])!r} }}"
            else:
                raise SystemExit(f"{rel}: geom type {kind} not handled")
            mat = attrs.get("material")
            m = dict(MATERIAL_DEFAULT)
            texture = "None"
            if mat and mat in materials:
                m.update(materials[mat].attrib)
                if "rgba" in g.attrib or ("rgba" in attrs and attrs["rgba"] != GEOM_DEFAULT["rgba"] and "rgba" in (classes.get(cls, {}) if cls else {})):
                    m["rgba"] = attrs["rgba"]
                tex = materials[mat].get("texture")
                if tex and tex in textures:
                    t = textures[tex]
                    cube = t.get("type", "cube") == "cube"
                    if m["texuniform"] != "false":
                        raise SystemExit(f"{rel}: texuniform on an object texture is not handled")
                    texture = (f'Some(TextureFact {{ file: "{norm(texdir, t.get("file"))}", cube: {str(cube).lower()}, '
                               f'repeat: {fmt(floats(m["texrepeat"]))} }})')
            else:
                m["rgba"] = attrs["rgba"]
            material = (f"MaterialFact {{ rgba: {fmt(floats(m['rgba']))}, specular: {float(m['specular'])!r}, "
                        f"shininess: {float(m['shininess'])!r}, reflectance: {float(m['reflectance'])!r}, "
                        f"emission: {float(m['emission'])!r}, texture: {texture} }}")
            parts.append(f'        PartFact {{ body: "{owner}", pos: {fmt(pos)}, quat: {fmt(quat)}, shape: {shape}, material: {material} }},')
        for child in body.findall("body"):
            local = (floats(child.get("pos", "0 0 0")), qnorm(floats(child.get("quat", "1 0 0 0"))))
            cc = child.get("childclass", childclass)
            if keep(child):
                visit(child, ([0.0] * 3, [1.0, 0.0, 0.0, 0.0]), child.get("name"), cc)
            else:
                visit(child, compose(frame, local), owner, cc)

    owner = "main" if root_name in ("object", None) else root_name
    visit(obj, ([0.0] * 3, [1.0, 0.0, 0.0, 0.0]), owner, obj.get("childclass"))
    return parts


def category_facts(assets, category, rel):
    parts = parts_of(assets, rel, "object", lambda b: b.find("joint") is not None)
    return f'    ("{category}", "{rel}", &[\n' + "\n".join(parts) + "\n    ]),"


SCENES = ["libero_tabletop_base_style", "libero_floor_base_style", "libero_kitchen_tabletop_base_style",
          "libero_living_room_tabletop_base_style", "libero_study_base_style"]


def scene_facts(assets, scene):
    rel = f"scenes/{scene}.xml"
    parts = parts_of(assets, rel, None, lambda b: False, meshes_only=True)
    return f'    ("{scene}", &[\n' + "\n".join(parts) + "\n    ]),"


ARM_BODIES = {"base", "link0", "link1", "link2", "link3", "link4", "link5", "link6", "link7", "right_hand"}
GRIPPER_BODIES = {"right_gripper", "leftfinger", "rightfinger"}


# robosuite's add_mount puts the mount's root at the Panda's base offset minus RethinkMount's
# top_offset (0, 0, -0.01): 1 cm above the arm's base frame.
MOUNT_Z = 0.01


def robot_facts(robot_assets):
    parts = parts_of(robot_assets, "robots/panda/robot.xml", "base", lambda b: b.get("name") in ARM_BODIES)
    parts += parts_of(robot_assets, "grippers/panda_gripper.xml", "right_gripper", lambda b: b.get("name") in GRIPPER_BODIES)
    # The pedestal of a mounted arm, as body `mount` (drawn on the base of mounted Pandas only).
    mount = parts_of(robot_assets, "mounts/rethink_mount.xml", "base", lambda b: False)
    for p in mount:
        head, rest = p.split("pos: [", 1)
        xyz, tail = rest.split("]", 1)
        x, y, z = (float(v) for v in xyz.split(","))
        parts.append(head.replace('body: "base"', 'body: "mount"') + f"pos: {fmt([x, y, z + MOUNT_Z])}" + tail)
    return parts


def main():
    assets, robot_assets = sys.argv[1], sys.argv[2]
    print("//! Generated by `scenes/tools/gen_look_facts.py` from LIBERO's and robosuite's asset XMLs: the")
    print("//! visual geoms of every catalog category and of the Panda (numbers and upstream paths only).")
    print("//! Do not edit by hand.")
    print()
    print("// Numbers as the upstream files write them (0.707107, 1.5708, 3.14159) or as the generator converts them.")
    print("#![allow(clippy::approx_constant)]")
    print()
    print("use super::parts::{MaterialFact, PartFact, Shape, TextureFact};")
    print()
    print("/// Category, its asset XML (relative to LIBERO's `assets/`), and its visual parts.")
    print(f"pub(crate) const CATEGORIES: [(&str, &str, &[PartFact]); {len(CATEGORIES)}] = [")
    for category, rel in CATEGORIES:
        print(category_facts(assets, category, rel))
    print("];")
    print()
    print("/// Scene XML (`scenes/<name>.xml` under LIBERO's `assets/`) and its decor, in the world frame.")
    print(f"pub(crate) const SCENES: [(&str, &[PartFact]); {len(SCENES)}] = [")
    for scene in SCENES:
        print(scene_facts(assets, scene))
    print("];")
    print()
    print("/// robosuite's Panda with its gripper (paths relative to robosuite's `models/assets`), by the")
    print("/// robot model's body names.")
    print("pub(crate) const PANDA: &[PartFact] = &[")
    print("\n".join(p[4:] for p in robot_facts(robot_assets)))
    print("];")


if __name__ == "__main__":
    main()
