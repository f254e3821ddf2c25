"""The start region: the trapezoid in front of the landmark where trials begin (paper Sec. II-C:
"a trapezoidal region in front of the target").

:class:`StartRegion` is a small frozen value: the trapezoid is a wedge with its apex at the
landmark's front plane (``x = 0``, ``y = 0``), opening towards the robot at
``half_angle_deg`` on either side of the approach axis, and cut at the distances ``near`` and
``far`` from that plane. Start headings are uniform in ``+-yaw_deg`` around facing the
landmark. It is the one place where the trapezoid's geometry is computed: the sampler of
:class:`docking.world.DockingEnv`, the floor plans of the figures, notebook 02 and the tests all
ask it.

Coordinates as in :mod:`docking.world`: the robot stands at negative ``x`` facing ``+x``; a
pose is ``[x, y, yaw]`` and its distance from the landmark's front plane is ``-x``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from docking.validate import check_real, normalise

__all__ = ["StartRegion"]


@dataclasses.dataclass(frozen=True)
class StartRegion:
    """The start trapezoid and the start headings.

    Attributes:
      near: Distance of the trapezoid's near edge from the landmark's front plane (m, > 0).
      far: Distance of its far edge (m, >= ``near``).
      half_angle_deg: Half the opening angle of the wedge (deg, in [0, 45)): the lateral
        half-width at distance ``d`` is ``d`` times the tangent of ``half_angle_deg``.
      yaw_deg: Start headings are uniform in ``+-yaw_deg`` around facing the landmark (deg).
    """

    near: float
    far: float
    half_angle_deg: float
    yaw_deg: float = 0.0

    def __post_init__(self):
        owner = "StartRegion"
        normalise(
            self,
            near=check_real(owner, "near", self.near, lo=0, lo_open=True),
            far=check_real(owner, "far", self.far, lo=0, lo_open=True),
            half_angle_deg=check_real(
                owner, "half_angle_deg", self.half_angle_deg, lo=0, hi=45, hi_open=True
            ),
            yaw_deg=check_real(owner, "yaw_deg", self.yaw_deg, lo=0, hi=90),
        )
        if self.far < self.near:
            raise ValueError(f"StartRegion.far must be >= near ({self.near}), got {self.far}")

    @classmethod
    def of(cls, world, near: float | None = None, far: float | None = None) -> StartRegion:
        """The start region of a :class:`~docking.world.WorldConfig` (its ``start_*`` fields),
        with ``near`` / ``far`` replaced if given."""
        return cls(
            near=world.start_near if near is None else near,
            far=world.start_far if far is None else far,
            half_angle_deg=world.start_half_angle_deg,
            yaw_deg=world.start_yaw_deg,
        )

    @property
    def tan(self) -> float:
        """The tangent of ``half_angle_deg``: the half-width per metre of distance."""
        return math.tan(np.radians(self.half_angle_deg))  # the trapezoid's one tangent

    def half_width(self, distance):
        """The lateral half-width of the wedge at ``distance`` (m) from the landmark's front
        plane (a number or an array)."""
        return distance * self.tan

    def corners(self) -> np.ndarray:
        """The four corners ``(x, y)``, shape ``(4, 2)``, in order: near left, far left, far
        right, near right (left = +y)."""
        near, far = self.near, self.far
        return np.array(
            [
                (-near, self.half_width(near)),
                (-far, self.half_width(far)),
                (-far, -self.half_width(far)),
                (-near, -self.half_width(near)),
            ]
        )

    def contains(self, pose, tol: float = 1e-9) -> bool:
        """Whether the reference point of ``pose`` (``[x, y, ...]``) lies in the trapezoid (to
        within ``tol`` metres); the heading is not checked."""
        distance, y = -float(pose[0]), float(pose[1])
        return bool(
            self.near - tol <= distance <= self.far + tol
            and abs(y) <= self.half_width(distance) + tol
        )

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """A pose ``[x, y, yaw]`` drawn uniformly over the trapezoid's area and the headings,
        with three draws from ``rng`` in this order: distance, lateral position, heading."""
        # Uniform over the area: the width grows linearly with the distance d, so d has
        # density proportional to d.
        d = np.sqrt(rng.uniform(self.near**2, self.far**2))
        y = rng.uniform(-1.0, 1.0) * d * self.tan
        yaw = np.radians(rng.uniform(-self.yaw_deg, self.yaw_deg))
        return np.array([-d, y, yaw])

    def with_edges(self, near: float, far: float) -> StartRegion:
        """The same wedge and headings cut at other distances."""
        return dataclasses.replace(self, near=near, far=far)
