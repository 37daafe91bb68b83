"""The test robots shared by the test modules (the bundled robot itself is the ``params``
fixture of conftest.py)."""

from __future__ import annotations

from diffbot.kinematics import DiffDriveParams

#: The course's robot without a motor limit: r = 0.035 m, b = 0.135 m.
BOT = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
#: The same robot with its 50 rpm motor limit (rad/s).
BOT_50_RPM = BOT.replace(max_wheel_speed=5.235987755982989)
