#!/usr/bin/env bash
# Install everything the tests need (Debian chromium included) and run the test suite.
# Usage: bash tests/install_and_run.sh [pytest args...]   (e.g. -m slow, or -m "slow or not slow")
# The tests run on every core (pytest-xdist, one test file per worker: its fixtures are built
# once); TEST_WORKERS=1 runs them in one process.
set -euo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

if ! command -v chromium >/dev/null 2>&1; then
  echo "== installing Debian chromium (browser tests drive it through Playwright)"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi

echo "== installing the project with its test extra"
python3 -m pip install --quiet --disable-pip-version-check -e ".[test]"

echo "== ruff"
python3 -m ruff check .

echo "== pytest"
set +e
python3 -m pytest -n "${TEST_WORKERS:-auto}" --dist loadfile "$@"
status=$?
set -e
# pytest exits 5 when it collected no tests: that is a failure of this script, not a pass.
exit "$status"
