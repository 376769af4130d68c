"""Make the explorer's vehicle meshes from trimesh primitives (run once; the .glb files are
committed): `python assets/make_meshes.py`.

Conventions the explorer relies on (explorer/vehicle.py): +z is the thrust axis (the vehicle
accelerates towards +z), the nozzle exit is at z = -0.5, +y is the vehicle's "up", and the
longest dimension is about 1, so the explorer scales a mesh by one number.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import trimesh
from trimesh.creation import annulus, box, cone, cylinder, uv_sphere

HERE = Path(__file__).parent

GOLD = (212, 175, 55)
SILVER = (200, 205, 215)
DARK = (60, 60, 66)
PANEL = (40, 70, 170)
WHITE = (235, 235, 240)
SHIELD = (120, 70, 40)
RUBBER = (30, 30, 34)
FLAME = (255, 170, 40)


def _paint(mesh: trimesh.Trimesh, rgb: tuple[int, int, int]) -> trimesh.Trimesh:
    mesh.visual = trimesh.visual.ColorVisuals(mesh, face_colors=[*rgb, 255])
    return mesh


def _at(mesh: trimesh.Trimesh, x: float = 0.0, y: float = 0.0, z: float = 0.0):
    mesh.apply_translation((x, y, z))
    return mesh


def _along(mesh: trimesh.Trimesh, axis: np.ndarray) -> trimesh.Trimesh:
    """Rotate a z-aligned primitive onto `axis`."""
    mesh.apply_transform(trimesh.geometry.align_vectors([0, 0, 1], axis))
    return mesh


def _nozzle(radius: float, length: float, top: float) -> trimesh.Trimesh:
    """A bell pointing down from z = top to the exit at z = top - length."""
    bell = cone(radius, length, sections=24)
    bell.apply_transform(trimesh.transformations.rotation_matrix(np.pi, [1, 0, 0]))
    return _paint(_at(bell, z=top), DARK)


def lander() -> list[trimesh.Trimesh]:
    """A lunar module: gold descent stage, silver cabin, four legs, the engine below."""
    parts = [_paint(_at(cylinder(0.3, 0.3, sections=8), z=-0.1), GOLD),
             _paint(_at(box((0.34, 0.34, 0.26)), z=0.18), SILVER),
             _paint(_at(cylinder(0.05, 0.06, sections=12), z=0.34), DARK),
             _nozzle(0.11, 0.25, -0.25)]
    for angle in np.arange(4) * np.pi / 2 + np.pi / 4:
        out = np.array([np.cos(angle), np.sin(angle), 0.0])
        top, foot = 0.25 * out + [0, 0, -0.05], 0.45 * out + [0, 0, -0.48]
        leg = cylinder(0.018, float(np.linalg.norm(foot - top)), sections=8)
        _along(leg, foot - top)
        parts.append(_paint(_at(leg, *(0.5 * (top + foot))), SILVER))
        parts.append(_paint(_at(cylinder(0.06, 0.015, sections=12), *foot), SILVER))
    return parts


def spacecraft() -> list[trimesh.Trimesh]:
    """A chaser spacecraft: a white bus, two blue solar wings, a dish and the main engine."""
    parts = [_paint(cylinder(0.16, 0.55, sections=16), WHITE),
             _paint(_at(box((1.0, 0.02, 0.22)), z=0.05), PANEL),
             _nozzle(0.09, 0.2, -0.275)]
    dish = uv_sphere(0.12, count=(12, 12))
    dish.apply_scale((1.0, 1.0, 0.35))
    parts.append(_paint(_at(dish, z=0.3), SILVER))
    return parts


def capsule() -> list[trimesh.Trimesh]:
    """A command module: a cone (apex +z) on a brown heat shield (at -z, faces the flow)."""
    body = cone(0.45, 0.75, sections=32)
    parts = [_paint(_at(body, z=-0.35), SILVER),
             _paint(_at(cylinder(0.47, 0.1, sections=32), z=-0.4), SHIELD),
             _paint(_at(cylinder(0.07, 0.08, sections=12), z=0.42), DARK)]
    return parts


def hovercraft() -> list[trimesh.Trimesh]:
    """A hovercraft: black skirt and deck flat in x-z (up is +y), a ducted fan at the back."""
    skirt = annulus(0.22, 0.32, 0.12, sections=32)
    skirt.apply_scale((1.0, 1.4, 1.0))
    _along(skirt, np.array([0.0, 1.0, 0.0]))
    parts = [_paint(_at(skirt, y=-0.06), RUBBER)]
    deck = box((0.44, 0.1, 0.62))
    parts.append(_paint(_at(deck, y=0.02), (230, 90, 40)))
    parts.append(_paint(_at(box((0.26, 0.12, 0.22)), y=0.12, z=0.1), WHITE))
    duct = annulus(0.1, 0.13, 0.08, sections=24)
    parts.append(_paint(_at(duct, y=0.2, z=-0.38), DARK))
    return parts


def plume() -> list[trimesh.Trimesh]:
    """Exhaust flame: a cone from its base at z = 0 to its tip at z = -1 (scaled by
    throttle), emissive so that it glows whatever the lighting."""
    flame = cone(0.12, 1.0, sections=24)
    flame.apply_transform(trimesh.transformations.rotation_matrix(np.pi, [1, 0, 0]))
    material = trimesh.visual.material.PBRMaterial(
        baseColorFactor=[40, 20, 0, 255], emissiveFactor=[c / 255 for c in FLAME],
        metallicFactor=0.0, roughnessFactor=1.0)
    flame.visual = trimesh.visual.TextureVisuals(material=material)
    return [flame]


VEHICLES = {"lander": lander, "spacecraft": spacecraft, "capsule": capsule,
            "hovercraft": hovercraft, "plume": plume}
# Which mesh a mission's vehicle uses (data, not code: missions not listed get "default").
MISSION_VEHICLES = {"lunar-landing": "lander", "apollo-reentry": "capsule",
                    "hovercraft": "hovercraft", "default": "spacecraft"}


def main() -> None:
    for name, make in VEHICLES.items():
        scene = trimesh.Scene(make())
        (HERE / f"{name}.glb").write_bytes(scene.export(file_type="glb"))
        print(f"{name}.glb: {sum(len(m.faces) for m in scene.geometry.values())} faces")
    (HERE / "vehicles.json").write_text(json.dumps(MISSION_VEHICLES, indent=2) + "\n")


if __name__ == "__main__":
    main()
