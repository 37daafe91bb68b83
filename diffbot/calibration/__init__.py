"""Odometry calibration: wheel radii and separation from UMBmark runs or from recordings
against a ground truth, and the results in the forms a robot's configuration takes.

- :mod:`~diffbot.calibration.umbmark`: Borenstein and Feng's square test.
- :mod:`~diffbot.calibration.fit`: least squares over windows of a recording (SciPy, a
  dependency of the base install); :mod:`~diffbot.calibration.fit_recordings` the same over
  recordings as read from files, one at a time.
- :mod:`~diffbot.calibration.results`: multipliers and xacro arguments.
- :mod:`~diffbot.calibration.apply`: calibrated copies of a controllers YAML or a description.
- :mod:`~diffbot.calibration.truth`: the ground truth of a simulated robot.

The derivations are in ``docs/calibration.md``.
"""

from __future__ import annotations

from diffbot.calibration.apply import ApplyResult, apply_to, calibrated_path
from diffbot.calibration.fit import DEFAULT_WINDOW, FitResult, fit
from diffbot.calibration.fit_recordings import fit_recording
from diffbot.calibration.results import (
    WheelGeometry,
    XacroArguments,
    controller_yaml_lines,
    multiplier_base,
    params_json,
    xacro_arguments,
    yaml_number,
)
from diffbot.calibration.truth import ground_truth, true_robot
from diffbot.calibration.umbmark import UmbmarkResult, umbmark, umbmark_segments
from diffbot.errors import CalibrationError

__all__ = [
    "DEFAULT_WINDOW",
    "ApplyResult",
    "CalibrationError",
    "FitResult",
    "UmbmarkResult",
    "WheelGeometry",
    "XacroArguments",
    "apply_to",
    "calibrated_path",
    "controller_yaml_lines",
    "fit",
    "fit_recording",
    "ground_truth",
    "multiplier_base",
    "params_json",
    "true_robot",
    "umbmark",
    "umbmark_segments",
    "xacro_arguments",
    "yaml_number",
]
