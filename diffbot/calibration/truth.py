"""Ground truth of a simulated robot whose real wheels and separation differ from the
description's: the poses that calibration data without a robot are checked against."""

from __future__ import annotations

from typing import TYPE_CHECKING

from diffbot.kinematics import DiffDriveParams

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.batch_odometry import PoseSeries
    from diffbot.trajectory import Plan

__all__ = ["TRUTH_COLUMNS", "ground_truth", "true_robot", "truth_rows"]

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


def ground_truth(plan: Plan, times: ArrayLike, robot: DiffDriveParams) -> PoseSeries:
    """Where ``robot`` really is when its wheels turn as ``plan`` commands, at ``times``.

    The wheels follow the commands exactly (encoder noise is in the readings, not the motion);
    within a segment their speeds are constant, so each step between samples is an exact arc and
    the poses are exact wherever the times include the segment boundaries (as
    :func:`diffbot.simulation.simulate`'s do).

    Args:
        plan: the commanded plan (made with the described robot).
        times: times since the start of the plan (s), increasing, shape (n,).
        robot: the real robot (:func:`true_robot`).

    Returns:
        x, y (m) and the unwrapped heading (rad) at each time, from pose (0, 0, 0).
    """
    from diffbot.batch_odometry import integrate
    from diffbot.trajectory import wheel_positions

    left, right = wheel_positions(plan, times)
    return integrate(robot, left, right)


def truth_rows(plan: Plan, times: ArrayLike, robot: DiffDriveParams) -> NDArray[np.float64]:
    """:func:`ground_truth` as rows x, y (m) and theta (rad, wrapped to (-pi, pi]), shape (3, n):
    the :data:`TRUTH_COLUMNS` of a simulation."""
    import numpy as np

    from diffbot.kinematics import norm_angle

    x, y, theta = ground_truth(plan, times, robot)
    return np.vstack((x, y, norm_angle(theta)))
