"""diffbot: exact kinematics, odometry and motion plans for differential-drive robots.

Quick use::

    import diffbot
    params = diffbot.load_params()                 # the bundled robot
    diffbot.inverse(params, 0.1, 0.0)              # WheelSpeeds(left=2.857..., right=2.857...)

SI units throughout: metres, seconds, radians, rad/s.
"""

from diffbot.errors import (
    DescriptionError,
    DiffbotError,
    DriveWheelError,
    OutputExistsError,
    PackageNotFoundError,
    ParameterError,
    PlanError,
    RecordingError,
    XacroError,
)
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
from diffbot.odometry import Odometry, OdometryMessage, PoseSeries, TransformStamped, integrate
from diffbot.urdf import BUNDLED_DESCRIPTION, derive_params, expand, load_params

__version__ = "0.1.0"

__all__ = [
    "BUNDLED_DESCRIPTION",
    "DescriptionError",
    "DiffDriveParams",
    "DiffbotError",
    "DriveWheelError",
    "Odometry",
    "OdometryMessage",
    "OutputExistsError",
    "PackageNotFoundError",
    "ParameterError",
    "PlanError",
    "Pose",
    "PoseSeries",
    "RecordingError",
    "TransformStamped",
    "Twist",
    "WheelSpeeds",
    "XacroError",
    "__version__",
    "derive_params",
    "expand",
    "forward",
    "integrate",
    "inverse",
    "joint_from_wheel",
    "limit_fraction",
    "load_params",
    "norm_angle",
    "rad_s_from_rpm",
    "rpm_from_rad_s",
    "saturate",
    "wheel_from_joint",
    "within_limit",
]
