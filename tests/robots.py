"""The test robots shared by the test modules (the bundled robot itself is the ``params``
fixture of conftest.py)."""

from __future__ import annotations

from diffbot.kinematics import DiffDriveParams

#: The course's robot without a motor limit: r = 0.035 m, b = 0.135 m.
BOT = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
#: The same robot with its 50 rpm motor limit (rad/s).
BOT_50_RPM = BOT.replace(max_wheel_speed=5.235987755982989)


def bundled_controllers(
    *parameters: str, name: str = "diffbot_base_controller", update_rate: int | None = None
) -> str:
    """A ros2_control controllers file for the bundled robot's joints and sizes: one
    diff_drive_controller ``name``, its ``parameters`` lines (``"open_loop: true"``) after the
    wheels, and the controller manager's ``update_rate`` when given."""
    rate = "" if update_rate is None else f"    update_rate: {update_rate}\n"
    extra = "".join(f"    {line}\n" for line in parameters)
    return (
        f"controller_manager:\n  ros__parameters:\n{rate}"
        f"    {name}:\n      type: diff_drive_controller/DiffDriveController\n"
        f"{name}:\n  ros__parameters:\n"
        '    left_wheel_names: ["front_left_wheel_joint"]\n'
        '    right_wheel_names: ["front_right_wheel_joint"]\n'
        "    wheel_separation: 0.135\n    wheel_radius: 0.035\n"
        f"{extra}"
    )


def two_wheel_urdf(
    *,
    radius: str = "0.05",
    left_xyz: str = "0 0.1 0",
    right_xyz: str = "0 -0.1 0",
    left_axis: str = "0 1 0",
    body: str = "",
    xacro: bool = False,
) -> str:
    """A robot with two drive wheels (r = 0.05 m, b = 0.2 m unless told otherwise), as URDF text;
    ``body`` is added inside ``<robot>``, and ``xacro`` declares the xacro namespace."""
    namespace = ' xmlns:xacro="http://www.ros.org/wiki/xacro"' if xacro else ""
    wheels = []
    for name, xyz, axis in (("left", left_xyz, left_axis), ("right", right_xyz, "0 1 0")):
        wheels.append(
            f'<joint name="{name}_wheel_joint" type="continuous"><parent link="base_link"/>'
            f'<child link="{name}_wheel"/><origin xyz="{xyz}"/><axis xyz="{axis}"/></joint>'
            f'<link name="{name}_wheel"><collision><origin rpy="1.5707963 0 0"/><geometry>'
            f'<cylinder radius="{radius}" length="0.02"/></geometry></collision></link>'
        )
    return (
        f'<?xml version="1.0"?>\n<robot name="two"{namespace}>\n<link name="base_link"/>\n'
        + "\n".join(wheels)
        + f"\n{body}\n</robot>\n"
    )


#: Joints named ``left`` and ``right``, with a 5 rad/s motor limit.
NAMED = DiffDriveParams(
    wheel_radius=0.035,
    wheel_separation=0.135,
    max_wheel_speed=5.0,
    left_joint="left",
    right_joint="right",
)
#: The same with the right joint mounted mirrored (sign -1).
MIRRORED = NAMED.replace(right_sign=-1)

#: Two drive wheels per side (a skid steer): front and rear on each side.
SKID = DiffDriveParams(
    wheel_radius=0.035,
    wheel_separation=0.135,
    left_joint="front_left",
    right_joint="front_right",
    left_joints=("front_left", "rear_left"),
    right_joints=("front_right", "rear_right"),
)


def sized_by_properties(body: str) -> str:
    """A xacro robot whose wheels take their size from the ``wheel_radius`` and
    ``wheel_separation`` properties that ``body`` defines (it goes first: xacro reads in
    document order)."""
    urdf = two_wheel_urdf(
        radius="${wheel_radius}",
        left_xyz="0 ${wheel_separation / 2} 0",
        right_xyz="0 ${-wheel_separation / 2} 0",
        xacro=True,
    )
    start = urdf.index(">", urdf.index("<robot")) + 1
    return f"{urdf[:start]}\n{body}{urdf[start:]}"
