"""The installed package (`pip install .`, not editable) carries what the app needs: the
vehicle meshes and every mission's help text."""

from __future__ import annotations

import subprocess
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
from explorer.scene import vehicle_mesh
import solvers
mesh = vehicle_mesh("lunar-landing")
assert mesh is not None and mesh[:4] == b"glTF", "no lander mesh"
missing = [m.key for m in solvers.list_missions() if not m.help]
assert not missing, f"no help text: {missing}"
print("ok", len(mesh))
"""


def test_a_wheel_install_ships_the_meshes_and_help(tmp_path):
    env = tmp_path / "venv"
    venv.EnvBuilder(system_site_packages=True, with_pip=True).create(env)
    python = env / "bin" / "python"
    subprocess.run([python, "-m", "pip", "install", "--quiet", "--no-deps", str(ROOT)],
                   check=True, cwd=tmp_path)
    out = subprocess.run([python, "-c", PROBE], cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("ok")
    located = subprocess.run([python, "-c", "import explorer; print(explorer.__file__)"],
                             cwd=tmp_path, capture_output=True, text=True, check=True)
    assert str(ROOT) not in located.stdout  # the installed copy, not this source tree
