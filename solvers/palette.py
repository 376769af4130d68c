"""The one palette every mission view draws with (sRGB), so colours mean the same thing in
every mission: where the vehicle starts, where it must arrive, bodies, references."""

from __future__ import annotations

RGB = tuple[int, int, int]

START: RGB = (255, 200, 80)  # where the vehicle starts
TARGET: RGB = (120, 255, 120)  # where it must arrive
LABEL: RGB = (255, 255, 255)  # a neutral marker
TARGET_BODY: RGB = (230, 230, 240)  # a target vehicle drawn as a small sphere

MOON: RGB = (170, 170, 165)
EARTH: RGB = (70, 120, 200)
SUN: RGB = (255, 210, 60)
ASTEROID: RGB = (200, 160, 120)
EARTH_ORBIT: RGB = (70, 130, 255)

ORBIT: RGB = (200, 200, 200)  # a reference orbit
AXIS: RGB = (110, 110, 130)  # an approach axis, a direction
GRID: RGB = (90, 90, 100)  # a ground grid
BOUND: RGB = (200, 120, 80)  # a state bound drawn in space
CONTROL_BOUND: RGB = (160, 110, 155)  # a control's bounds around its arrows (muted magenta)
FREE_MOTION: RGB = (150, 150, 150)  # motion without control
REFERENCE: RGB = (255, 120, 200)  # an independent (e.g. maximum-principle) optimum
NONLINEAR: RGB = (255, 110, 110)  # a re-propagation in a higher-fidelity model
HIGHLIGHT: RGB = (255, 210, 90)  # the target of a relative transfer
