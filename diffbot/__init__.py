"""diffbot: exact kinematics, odometry and motion plans for differential-drive robots.

Quick use::

    import diffbot
    params = diffbot.load_params()                 # the bundled robot
    diffbot.inverse(params, 0.1, 0.0)              # WheelSpeeds(left=2.857..., right=2.857...)
    p = diffbot.plan(diffbot.parse_plan("ccw 0.25 180 10s; straight 1 10s"), params)
    p.final_pose                                   # Pose(x=-1.0, y=0.5..., theta=3.14159...)

SI units throughout: metres, seconds, radians, rad/s.
"""

from diffbot.lazy import lazy_names

TYPE_CHECKING = False

# Every name loads on first use: a command pays only for what it needs, and the command line's
# entry point takes signals before anything heavier than this file has loaded.
if TYPE_CHECKING:
    from diffbot.errors import (
        DescriptionError,
        DiffbotError,
        DriveWheelError,
        NotDifferentialError,
        OutputExistsError,
        PackageNotFoundError,
        ParameterError,
        PlanError,
        RecordingError,
        XacroError,
    )
    from diffbot.execution import Execution, execute_plan
    from diffbot.follow import Follower
    from diffbot.goals import plan_through, plan_to
    from diffbot.io.command_bag import write_command_bag
    from diffbot.kinematics import (
        DiffDriveParams,
        Pose,
        Twist,
        WheelSpeeds,
        forward,
        inverse,
        joint_from_wheel,
        limit_fraction,
        norm_angle,
        rad_s_from_rpm,
        rpm_from_rad_s,
        saturate,
        wheel_from_joint,
        within_limit,
    )
    from diffbot.odometry import Odometry, PoseSeries, integrate
    from diffbot.planfile import format_plan, load_plan, parse_plan
    from diffbot.profiles import Limits, PathLimits
    from diffbot.ramps import CommandStream, RampedPlan, controller_limits, ramp
    from diffbot.recordings import read_recording
    from diffbot.ros.messages import OdometryMessage, TransformStamped
    from diffbot.trajectory import (
        EXAMPLES,
        Arc,
        Plan,
        PlannedSegment,
        Segment,
        Spin,
        Straight,
        Violation,
        plan,
        pose_at,
        wheel_positions,
    )
    from diffbot.urdf import BUNDLED_DESCRIPTION, derive_params, expand, load_params

_LAZY = {
    "DescriptionError": "diffbot.errors",
    "DiffbotError": "diffbot.errors",
    "DriveWheelError": "diffbot.errors",
    "NotDifferentialError": "diffbot.errors",
    "OutputExistsError": "diffbot.errors",
    "PackageNotFoundError": "diffbot.errors",
    "ParameterError": "diffbot.errors",
    "PlanError": "diffbot.errors",
    "RecordingError": "diffbot.errors",
    "XacroError": "diffbot.errors",
    "DiffDriveParams": "diffbot.kinematics",
    "Pose": "diffbot.kinematics",
    "Twist": "diffbot.kinematics",
    "WheelSpeeds": "diffbot.kinematics",
    "forward": "diffbot.kinematics",
    "inverse": "diffbot.kinematics",
    "joint_from_wheel": "diffbot.kinematics",
    "limit_fraction": "diffbot.kinematics",
    "norm_angle": "diffbot.kinematics",
    "rad_s_from_rpm": "diffbot.kinematics",
    "rpm_from_rad_s": "diffbot.kinematics",
    "saturate": "diffbot.kinematics",
    "wheel_from_joint": "diffbot.kinematics",
    "within_limit": "diffbot.kinematics",
    "BUNDLED_DESCRIPTION": "diffbot.urdf",
    "derive_params": "diffbot.urdf",
    "expand": "diffbot.urdf",
    "load_params": "diffbot.urdf",
    "Odometry": "diffbot.odometry",
    "OdometryMessage": "diffbot.ros.messages",
    "PoseSeries": "diffbot.odometry",
    "TransformStamped": "diffbot.ros.messages",
    "integrate": "diffbot.odometry",
    "EXAMPLES": "diffbot.trajectory",
    "Arc": "diffbot.trajectory",
    "Plan": "diffbot.trajectory",
    "PlannedSegment": "diffbot.trajectory",
    "Segment": "diffbot.trajectory",
    "Spin": "diffbot.trajectory",
    "Straight": "diffbot.trajectory",
    "Violation": "diffbot.trajectory",
    "format_plan": "diffbot.planfile",
    "load_plan": "diffbot.planfile",
    "parse_plan": "diffbot.planfile",
    "plan": "diffbot.trajectory",
    "pose_at": "diffbot.trajectory",
    "wheel_positions": "diffbot.trajectory",
    "Limits": "diffbot.profiles",
    "PathLimits": "diffbot.profiles",
    "CommandStream": "diffbot.ramps",
    "RampedPlan": "diffbot.ramps",
    "controller_limits": "diffbot.ramps",
    "ramp": "diffbot.ramps",
    "Execution": "diffbot.execution",
    "execute_plan": "diffbot.execution",
    "Follower": "diffbot.follow",
    "write_command_bag": "diffbot.io.command_bag",
    "plan_to": "diffbot.goals",
    "plan_through": "diffbot.goals",
    "read_recording": "diffbot.recordings",
}


__getattr__, __dir__ = lazy_names("diffbot", _LAZY, globals())


__version__ = "0.1.0"

__all__ = [
    "BUNDLED_DESCRIPTION",
    "EXAMPLES",
    "Arc",
    "CommandStream",
    "DescriptionError",
    "DiffDriveParams",
    "DiffbotError",
    "DriveWheelError",
    "Execution",
    "Follower",
    "Limits",
    "NotDifferentialError",
    "Odometry",
    "OdometryMessage",
    "OutputExistsError",
    "PackageNotFoundError",
    "ParameterError",
    "PathLimits",
    "Plan",
    "PlanError",
    "PlannedSegment",
    "Pose",
    "PoseSeries",
    "RampedPlan",
    "RecordingError",
    "Segment",
    "Spin",
    "Straight",
    "TransformStamped",
    "Twist",
    "Violation",
    "WheelSpeeds",
    "XacroError",
    "__version__",
    "controller_limits",
    "derive_params",
    "execute_plan",
    "expand",
    "format_plan",
    "forward",
    "integrate",
    "inverse",
    "joint_from_wheel",
    "limit_fraction",
    "load_params",
    "load_plan",
    "norm_angle",
    "parse_plan",
    "plan",
    "plan_through",
    "plan_to",
    "pose_at",
    "rad_s_from_rpm",
    "ramp",
    "read_recording",
    "rpm_from_rad_s",
    "saturate",
    "wheel_from_joint",
    "wheel_positions",
    "within_limit",
    "write_command_bag",
]
