"""The installed package (`pip install .`, not editable) carries what the app needs: the
vehicle meshes and every mission's help text."""

from __future__ import annotations

import site
import subprocess
import sysconfig
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
from explorer.asset_files import vehicle_mesh
import solvers
mesh = vehicle_mesh("lunar-landing")
assert mesh is not None and mesh[:4] == b"glTF", "no lander mesh"
missing = [m.key for m in solvers.list_missions() if not m.help]
assert not missing, f"no help text: {missing}"
print("ok", len(mesh))
"""


def running_site_packages() -> list[str]:
    """The site folders of the interpreter running the tests (a venv's own, or the system's).

    `system_site_packages=True` would give the child the *base* interpreter's folders, which
    inside a virtual environment lack the dependencies (viser, casadi...)."""
    folders = [sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]]
    folders += site.getsitepackages()
    return list(dict.fromkeys(f for f in folders if Path(f).is_dir()))


def child_environment(path: Path) -> Path:
    """A fresh venv whose site-packages comes first and then sees the running interpreter's
    packages as plain path entries (their .pth files, e.g. this project's editable install,
    are not processed, so the copy installed into the child is the one imported)."""
    venv.EnvBuilder(with_pip=True).create(path)
    python = path / "bin" / "python"
    child_site = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True, text=True, check=True).stdout.strip()
    (Path(child_site) / "parent_site.pth").write_text("\n".join(running_site_packages()) + "\n")
    return python


def test_a_wheel_install_ships_the_meshes_and_help(tmp_path):
    python = child_environment(tmp_path / "venv")
    subprocess.run([python, "-m", "pip", "install", "--quiet", "--no-deps",
                    "--disable-pip-version-check", str(ROOT)], check=True, cwd=tmp_path)
    out = subprocess.run([python, "-c", PROBE], cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("ok")
    located = subprocess.run([python, "-c", "import explorer; print(explorer.__file__)"],
                             cwd=tmp_path, capture_output=True, text=True, check=True)
    assert str(ROOT) not in located.stdout  # the installed copy, not this source tree

