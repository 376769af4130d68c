"""The files of the installed `assets` package: vehicle meshes (by mission) and the plume."""

from __future__ import annotations

import json
from importlib import resources


def asset_bytes(name: str) -> bytes | None:
    """A file of the installed `assets` package (None if missing)."""
    try:
        return resources.files("assets").joinpath(name).read_bytes()
    except (FileNotFoundError, ModuleNotFoundError, OSError):
        return None


def vehicle_mesh(vehicle: str) -> bytes | None:
    """GLB bytes of a vehicle (a mission key or mesh name of assets/vehicles.json)."""
    table_bytes = asset_bytes("vehicles.json")
    if table_bytes is None:
        return None
    table = json.loads(table_bytes)
    return asset_bytes(f"{table.get(vehicle, table['default'])}.glb")
