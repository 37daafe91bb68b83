"""Mathematical notation shared by every language: symbols, formulas and units.

Formulas are :class:`string.Template` strings whose ``$name`` placeholders are symbol keys; they
are written once as plain text (Unicode) and once as LaTeX, with the placeholders in the same
order in both, so a reader (or a test) finds the substituted numbers in the same sequence.
"""

from __future__ import annotations

from typing import Final, NamedTuple

__all__ = ["FORMULAS", "MINUS", "MIRRORED", "SYMBOLS", "UNITS", "Notation"]

#: The subtraction operator of plain-text formulas; numbers keep the ASCII hyphen, so that they
#: can be copied into a calculator.
MINUS: Final = "\N{MINUS SIGN}"


class Notation(NamedTuple):
    """One piece of notation as plain text and as LaTeX (math mode)."""

    text: str
    latex: str


SYMBOLS: Final[dict[str, Notation]] = {
    "r": Notation("r", "r"),
    "rL": Notation("r_L", "r_L"),
    "rR": Notation("r_R", "r_R"),
    "b": Notation("b", "b"),
    "v": Notation("v", "v"),
    "w": Notation("ω", r"\omega"),
    "wL": Notation("ω_L", r"\omega_L"),
    "wR": Notation("ω_R", r"\omega_R"),
    "wmax": Notation("ω_max", r"\omega_{\max}"),
    "f": Notation("f", "f"),
    "s": Notation("s", "s"),
    "t": Notation("t", "t"),
    "R": Notation("R", "R"),
    "dtheta": Notation("Δθ", r"\Delta\theta"),
    "x0": Notation("x₀", "x_0"),
    "y0": Notation("y₀", "y_0"),
    "th0": Notation("θ₀", r"\theta_0"),
    "x1": Notation("x₁", "x_1"),
    "y1": Notation("y₁", "y_1"),
    "th1": Notation("θ₁", r"\theta_1"),
    "phiL0": Notation("φ_L0", r"\varphi_{L,0}"),
    "phiL1": Notation("φ_L1", r"\varphi_{L,1}"),
    "phiR0": Notation("φ_R0", r"\varphi_{R,0}"),
    "phiR1": Notation("φ_R1", r"\varphi_{R,1}"),
    "dL": Notation("d_L", "d_L"),
    "dR": Notation("d_R", "d_R"),
    "ds": Notation("ds", "ds"),
    "dth": Notation("dθ", r"d\theta"),
    "c": Notation("c", "c"),
    "dt": Notation("Δt", r"\Delta t"),
    "qL": Notation("q_L", "q_L"),
    "qR": Notation("q_R", "q_R"),
    "qL0": Notation("q_L0", "q_{L,0}"),
    "qL1": Notation("q_L1", "q_{L,1}"),
    "qR0": Notation("q_R0", "q_{R,0}"),
    "qR1": Notation("q_R1", "q_{R,1}"),
}

#: The symbols a mirrored joint axis flips: joint values (q) and wheel-ground values (ω, φ).
MIRRORED = ("qL", "qR", "wL", "wR", "qL0", "qL1", "qR0", "qR1")

FORMULAS: Final[dict[str, Notation]] = {
    "ik_left": Notation(f"($v {MINUS} $w·$b/2) / $r", r"\frac{$v - $w \cdot $b/2}{$r}"),
    "ik_right": Notation("($v + $w·$b/2) / $r", r"\frac{$v + $w \cdot $b/2}{$r}"),
    "ik_left_sides": Notation(f"($v {MINUS} $w·$b/2) / $rL", r"\frac{$v - $w \cdot $b/2}{$rL}"),
    "ik_right_sides": Notation("($v + $w·$b/2) / $rR", r"\frac{$v + $w \cdot $b/2}{$rR}"),
    "fk_linear_sides": Notation(
        "($rL·$wL + $rR·$wR) / 2", r"\frac{$rL \cdot $wL + $rR \cdot $wR}{2}"
    ),
    "fk_angular_sides": Notation(
        f"($rR·$wR {MINUS} $rL·$wL) / $b", r"\frac{$rR \cdot $wR - $rL \cdot $wL}{$b}"
    ),
    "fk_linear": Notation("$r·($wL + $wR) / 2", r"\frac{$r \cdot ($wL + $wR)}{2}"),
    "fk_angular": Notation(f"$r·($wR {MINUS} $wL) / $b", r"\frac{$r \cdot ($wR - $wL)}{$b}"),
    "limit": Notation("max(|$wL|, |$wR|) / $wmax", r"\frac{\max(|$wL|, |$wR|)}{$wmax}"),
    "arc_length": Notation("$R·$dtheta", r"$R \cdot $dtheta"),
    "speed": Notation("$s / $t", r"\frac{$s}{$t}"),
    "turn_rate": Notation("$dtheta / $t", r"\frac{$dtheta}{$t}"),
    "arc_speed": Notation("$w·$R", r"$w \cdot $R"),
    "pose_x": Notation(
        "$x0 + $s·sinc($dtheta/2)·cos($th0 + $dtheta/2)",
        r"$x0 + $s \cdot \mathrm{sinc}\left(\frac{$dtheta}{2}\right)"
        r" \cos\left($th0 + \frac{$dtheta}{2}\right)",
    ),
    "pose_y": Notation(
        "$y0 + $s·sinc($dtheta/2)·sin($th0 + $dtheta/2)",
        r"$y0 + $s \cdot \mathrm{sinc}\left(\frac{$dtheta}{2}\right)"
        r" \sin\left($th0 + \frac{$dtheta}{2}\right)",
    ),
    "pose_theta": Notation("wrap($th0 + $dtheta)", r"\mathrm{wrap}($th0 + $dtheta)"),
    "wheel_arc_left": Notation(f"$r·($phiL1 {MINUS} $phiL0)", r"$r \cdot ($phiL1 - $phiL0)"),
    "wheel_arc_right": Notation(f"$r·($phiR1 {MINUS} $phiR0)", r"$r \cdot ($phiR1 - $phiR0)"),
    "wheel_arc_left_sides": Notation(
        f"$rL·($phiL1 {MINUS} $phiL0)", r"$rL \cdot ($phiL1 - $phiL0)"
    ),
    "wheel_arc_right_sides": Notation(
        f"$rR·($phiR1 {MINUS} $phiR0)", r"$rR \cdot ($phiR1 - $phiR0)"
    ),
    "odom_ds": Notation("($dL + $dR) / 2", r"\frac{$dL + $dR}{2}"),
    "odom_dth": Notation(f"($dR {MINUS} $dL) / $b", r"\frac{$dR - $dL}{$b}"),
    "chord": Notation("$ds·sinc($dth/2)", r"$ds \cdot \mathrm{sinc}\left(\frac{$dth}{2}\right)"),
    "odom_x": Notation(
        "$x0 + $c·cos($th0 + $dth/2)", r"$x0 + $c \cos\left($th0 + \frac{$dth}{2}\right)"
    ),
    "odom_y": Notation(
        "$y0 + $c·sin($th0 + $dth/2)", r"$y0 + $c \sin\left($th0 + \frac{$dth}{2}\right)"
    ),
    "odom_theta": Notation("wrap($th0 + $dth)", r"\mathrm{wrap}($th0 + $dth)"),
    "odom_v": Notation("$ds / $dt", r"\frac{$ds}{$dt}"),
    "odom_w": Notation("$dth / $dt", r"\frac{$dth}{$dt}"),
    # A joint whose axis is mirrored turns the other way: each value changes sign.
    **{f"mirror_{name}": Notation(f"{MINUS}${name}", f"-${name}") for name in MIRRORED},
}

UNITS: Final[dict[str, Notation]] = {
    "": Notation("", ""),
    "m": Notation("m", r"\mathrm{m}"),
    "s": Notation("s", r"\mathrm{s}"),
    "rad": Notation("rad", r"\mathrm{rad}"),
    "deg": Notation("°", r"^\circ"),
    "m/s": Notation("m/s", r"\mathrm{m/s}"),
    "rad/s": Notation("rad/s", r"\mathrm{rad/s}"),
    "rpm": Notation("rpm", r"\mathrm{rpm}"),
    "%": Notation("%", r"\%"),
}
