"""Ground truth of a simulated robot whose real wheels and separation differ from the
description's: the poses that calibration data without a robot are checked against."""

from __future__ import annotations

from typing import TYPE_CHECKING

from diffbot.kinematics import DiffDriveParams, Pose

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.batch_odometry import PoseSeries
    from diffbot.simulation import Motion
    from diffbot.trajectory import Plan

__all__ = ["TRUTH_COLUMNS", "TruthStream", "ground_truth", "true_robot", "truth_rows"]

#: The names of the ground-truth pose columns of a simulation's CSV.
TRUTH_COLUMNS = ("x", "y", "theta")


def true_robot(
    params: DiffDriveParams,
    radii: tuple[float, float] | None = None,
    separation: float | None = None,
) -> DiffDriveParams:
    """The robot as it really is: the description's, with its real radii and separation.

    Args:
        params: the robot as described (joints, direction signs).
        radii: the real left and right wheel radii (m); None keeps the described ones.
        separation: the real wheel separation (m); None keeps the described one.

    Raises:
        ParameterError: a radius or separation that is not a positive finite number.
    """
    left, right = params.radii if radii is None else radii
    return params.replace(
        wheel_radius=0.5 * (left + right),
        left_wheel_radius=left,
        right_wheel_radius=right,
        wheel_separation=params.wheel_separation if separation is None else separation,
        max_wheel_speed=None,
    )


def ground_truth(plan: Plan | Motion, times: ArrayLike, robot: DiffDriveParams) -> PoseSeries:
    """Where ``robot`` really is when its wheels turn as ``plan`` commands, at ``times``.

    The wheels follow the commands exactly (encoder noise is in the readings, not the motion);
    between two changes of curvature their speeds keep one ratio, so each step between samples
    is an exact arc and the poses are exact wherever the times include those changes (the
    segment boundaries, as :func:`diffbot.simulation.simulate`'s samples do).

    Args:
        plan: the commanded plan (made with the described robot), or the motion the wheels
            follow instead (a ramped plan, what a controller executed).
        times: times since the start of the plan (s), increasing, shape (n,).
        robot: the real robot (:func:`true_robot`).

    Returns:
        x, y (m) and the unwrapped heading (rad) at each time, from pose (0, 0, 0).
    """
    from diffbot.batch_odometry import integrate

    left, right = _wheels(plan, times)
    return integrate(robot, left, right)


def _wheels(plan: Plan | Motion, times: ArrayLike) -> tuple[NDArray[np.float64], ...]:
    from diffbot import trajectory

    if isinstance(plan, trajectory.Plan):
        return trajectory.wheel_positions(plan, times)
    return plan.wheel_positions(times)


class TruthStream:
    """:func:`ground_truth` chunk by chunk, for a simulation written as it is made: each call
    continues from where the last one ended.

    Args:
        plan: the commanded plan, or the motion the wheels follow.
        robot: the real robot (:func:`true_robot`).
    """

    def __init__(self, plan: Plan | Motion, robot: DiffDriveParams) -> None:
        self.plan = plan
        self.robot = robot
        self._last: tuple[float, float, float, float, float] | None = None
        self._final: Pose | None = None

    def rows(self, times: ArrayLike) -> NDArray[np.float64]:
        """Rows x, y (m) and theta (rad, wrapped to (-pi, pi]) at ``times`` (s, increasing and
        after the last call's), shape (3, n): the :data:`TRUTH_COLUMNS` of a simulation."""
        import numpy as np

        from diffbot.batch_odometry import integrate
        from diffbot.kinematics import norm_angle

        left, right = _wheels(self.plan, times)
        if left.size == 0:
            return np.empty((3, 0))
        if self._last is None:
            x, y, theta = integrate(self.robot, left, right)
        else:
            l0, r0, x0, y0, theta0 = self._last
            track = integrate(self.robot, np.r_[l0, left], np.r_[r0, right], x0, y0, theta0)
            x, y, theta = track.x[1:], track.y[1:], track.theta[1:]
        self._last = (
            float(left[-1]),
            float(right[-1]),
            float(x[-1]),
            float(y[-1]),
            float(theta[-1]),
        )
        rows = np.vstack((x, y, norm_angle(theta)))
        self._final = Pose(*(float(v) for v in rows[:, -1]))
        return rows

    @property
    def final(self) -> Pose | None:
        """The last row given, as a pose (m, m, rad in (-pi, pi]): where the real robot ended
        once every sample is taken; None before any."""
        return self._final


def truth_rows(
    plan: Plan | Motion, times: ArrayLike, robot: DiffDriveParams
) -> NDArray[np.float64]:
    """:func:`ground_truth` as rows x, y (m) and theta (rad, wrapped to (-pi, pi]), shape (3, n):
    the :data:`TRUTH_COLUMNS` of a simulation."""
    return TruthStream(plan, robot).rows(times)
