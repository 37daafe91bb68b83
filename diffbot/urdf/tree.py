"""The link/joint tree of a URDF: joints as plain records, link frames relative to the base."""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from typing import TYPE_CHECKING

from diffbot.errors import DescriptionError, NotDifferentialError
from diffbot.urdf.urdf_model import LinkModel, RobotModel, read_robot
from diffbot.urdf.xacro import check_xml

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = [
    "FULL_TURN_SLACK",
    "MAX_OFFSET",
    "Joint",
    "Tree",
    "check_not_steered",
    "joints_of",
    "parse_urdf",
]

#: Farthest a joint may sit from its parent link (m): beyond, a description is taken for a unit
#: mistake or a hostile file, and its frames would lose all precision or overflow.
MAX_OFFSET = 1e6
#: A revolute joint whose range falls short of a turn by less than this (rad) turns all the way
#: round: descriptions write the limits of a free swivel as +-3.14159 or +-3.14.
FULL_TURN_SLACK = 0.01


@dataclass(frozen=True)
class Joint:
    name: str
    type: str
    parent: str
    child: str
    origin: NDArray[np.float64]  # 4x4, parent frame -> joint frame
    axis: NDArray[np.float64]  # unit, joint frame
    velocity_limit: float | None
    mimic: bool = False
    full_turn: bool = False  # revolute with a range of at least one turn: a wheel all the same
    rest: float = 0.0  # position at rest (m or rad): 0, clamped into the joint's limits

    def rest_transform(self) -> NDArray[np.float64]:
        """The joint's motion at its rest position (4x4): identity when ``rest`` is 0."""
        import numpy as np

        motion = np.eye(4)
        if self.type == "prismatic":
            motion[:3, 3] = self.axis * self.rest
        elif self.type in ("revolute", "continuous"):
            x, y, z = self.axis
            c, s, t = math.cos(self.rest), math.sin(self.rest), 1.0 - math.cos(self.rest)
            motion[:3, :3] = [
                [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
            ]
        return motion


def parse_urdf(text: str, source: str) -> RobotModel:
    """Check URDF text and read its links and joints (:mod:`diffbot.urdf.urdf_model`)."""
    root = check_xml(text, source)
    if root.find("link") is None:
        raise DescriptionError(
            f"{source}: the description defines no links: is it a file of macros, meant to "
            "be included by the robot's top-level description?"
        )
    return read_robot(root, source)


def joints_of(robot: RobotModel, source: str) -> dict[str, Joint]:
    import numpy as np

    link_names = {link.name for link in robot.links}
    joints: dict[str, Joint] = {}
    for j in robot.joints:
        ends: list[str] = []
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link is None or link not in link_names:
                raise DescriptionError(
                    f"{source}: joint {j.name!r} has unknown {role} link {link!r}"
                )
            ends.append(link)
        origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float)
        axis = np.asarray(j.axis, dtype=float)
        if axis.shape != (3,):
            raise DescriptionError(
                f"{source}: joint {j.name!r} has an axis of {axis.size} numbers, not 3 (x y z)"
            )
        norm = float(np.linalg.norm(axis))
        if not np.all(np.isfinite(origin)) or not math.isfinite(norm):
            raise DescriptionError(f"{source}: joint {j.name!r} has a non-finite origin or axis")
        offset = float(np.max(np.abs(origin[:3, 3])))
        if offset > MAX_OFFSET:
            raise DescriptionError(
                f"{source}: joint {j.name!r} lies {offset:g} m from its parent link, more than "
                f"{MAX_OFFSET:g} m: not a robot's size"
            )
        if norm == 0.0 and j.type in ("continuous", "revolute", "prismatic"):
            raise DescriptionError(f"{source}: joint {j.name!r} has a zero axis")
        velocity = None
        full_turn = False
        rest = 0.0
        if j.limit is not None:
            if j.limit.velocity is not None:
                velocity = float(j.limit.velocity)
            if j.limit.lower is not None and j.limit.upper is not None:
                span = float(j.limit.upper) - float(j.limit.lower)
                full_turn = span >= 2.0 * math.pi - FULL_TURN_SLACK
                if j.type in ("prismatic", "revolute") and not full_turn:
                    rest = min(max(0.0, float(j.limit.lower)), float(j.limit.upper))
        joints[j.name] = Joint(
            j.name,
            str(j.type),
            ends[0],
            ends[1],
            origin,
            axis / (norm or 1.0),
            velocity,
            mimic=j.mimic is not None,
            full_turn=full_turn,
            rest=rest,
        )
    return joints


class Tree:
    """Link frames at the zero configuration, relative to the base link."""

    def __init__(self, robot: RobotModel, joints: dict[str, Joint], source: str) -> None:
        import numpy as np

        self.joints = joints
        self.parent_joint: dict[str, Joint] = {}
        for joint in joints.values():
            if joint.child in self.parent_joint:
                other = self.parent_joint[joint.child].name
                raise DescriptionError(
                    f"{source}: link {joint.child!r} has two parent joints "
                    f"({other!r} and {joint.name!r})"
                )
            self.parent_joint[joint.child] = joint
        links = [link.name for link in robot.links]
        duplicates = sorted(name for name, count in Counter(links).items() if count > 1)
        if duplicates:
            raise DescriptionError(f"{source}: links defined more than once: {duplicates}")
        roots = [name for name in links if name not in self.parent_joint]
        if len(roots) != 1:
            what = "no root link (a cycle)" if not roots else f"several root links {roots}"
            raise DescriptionError(f"{source}: the links do not form one tree: {what}")
        self._check_no_cycle(links, source)
        self.links: dict[str, LinkModel] = {link.name: link for link in robot.links}
        self.base = "base_link" if "base_link" in self.links else roots[0]
        self._from_root: dict[str, NDArray[np.float64]] = {roots[0]: np.eye(4)}
        self._base_inv = np.linalg.inv(self._root_frame(self.base))

    def _check_no_cycle(self, links: list[str], source: str) -> None:
        """Refuse a cycle of parent joints; each link is walked up once (linear time)."""
        rooted: set[str] = set()  # links whose walk up ends at the root
        for name in links:
            walk: list[str] = []
            on_walk: set[str] = set()
            node = name
            while node not in rooted:
                if node in on_walk:
                    raise DescriptionError(
                        f"{source}: the links do not form one tree: a cycle through {node!r}"
                    )
                walk.append(node)
                on_walk.add(node)
                if node not in self.parent_joint:
                    break
                node = self.parent_joint[node].parent
            rooted.update(walk)

    def _root_frame(self, link: str) -> NDArray[np.float64]:
        chain: list[Joint] = []
        node = link
        while node not in self._from_root:
            joint = self.parent_joint[node]
            chain.append(joint)
            node = joint.parent
        frame = self._from_root[node]
        for joint in reversed(chain):
            frame = frame @ joint.origin
            if joint.rest != 0.0:
                frame = frame @ joint.rest_transform()
            self._from_root[joint.child] = frame
        return frame

    def frame(self, link: str) -> NDArray[np.float64]:
        """The link's frame in the base frame (4x4)."""
        return self._base_inv @ self._root_frame(link)

    def ancestors(self, link: str) -> list[str]:
        out = [link]
        while out[-1] in self.parent_joint:
            out.append(self.parent_joint[out[-1]].parent)
        return out

    def joints_between(self, a: str, b: str) -> list[Joint]:
        """The joints on the path between two links."""
        up_a, up_b = self.ancestors(a), self.ancestors(b)
        above_b = set(up_b)
        common = next(link for link in up_a if link in above_b)
        path = up_a[: up_a.index(common)] + up_b[: up_b.index(common)]
        return [self.parent_joint[link] for link in path]


#: A joint axis counts as vertical (a steering joint's) or lateral (a wheel's) when its z or y
#: component (unit axis, base frame) is at least this.
_ALIGNED_MIN = math.cos(math.radians(25.0))


def _axis_in_base(tree: Tree, joint: Joint) -> NDArray[np.float64]:
    return (tree.frame(joint.parent) @ joint.origin)[:3, :3] @ joint.axis


def _rotary(joint: Joint) -> bool:
    return joint.type == "continuous" or (joint.type == "revolute" and joint.full_turn)


def _steers(tree: Tree, joint: Joint) -> bool:
    """Whether a joint steers: revolute about the vertical axis, with a range short of a turn
    (a free swivel, continuous or limited to a whole turn, is a caster's)."""
    return (
        joint.type == "revolute"
        and not joint.full_turn
        and abs(float(_axis_in_base(tree, joint)[2])) >= _ALIGNED_MIN
    )


def steered_wheels(tree: Tree) -> dict[str, list[str]]:
    """The wheel joints that turn on steering joints, each with its steering joints (base side
    first): wheel joints are continuous (or whole-turn revolute) joints whose axis is lateral in
    the base frame at rest, hanging from the base through no other free joint."""
    found: dict[str, list[str]] = {}
    for joint in tree.joints.values():
        if not _rotary(joint) or abs(float(_axis_in_base(tree, joint)[1])) < _ALIGNED_MIN:
            continue
        chain = tree.joints_between(joint.parent, tree.base)
        if any(_rotary(j) or j.type in ("floating", "planar") for j in chain):
            continue  # under a free joint (an arm's, a caster's): no wheel of the base
        steering = [j.name for j in reversed(chain) if _steers(tree, j)]
        if steering:
            found[joint.name] = steering
    return found


def check_not_steered(tree: Tree, source: str) -> None:
    """Refuse a robot whose wheels steer (Ackermann, tricycle, swerve): its wheel speeds do not
    follow from a body twist as a differential drive's do, and taking it for a skid steer
    would be wrong.

    Raises:
        NotDifferentialError: a wheel turns on a steering joint; the message names the steering
            joints, and ``fields["steering_joints"]`` lists them.
    """
    steered = steered_wheels(tree)
    if not steered:
        return
    steering: list[str] = []
    for names in steered.values():
        steering += [name for name in names if name not in steering]
    raise NotDifferentialError(
        f"{source}: a steered robot, not a differential drive: the wheel joint(s) "
        f"{sorted(steered)} turn with the steering joint(s) {steering} (limited, about the "
        "vertical axis)",
        path=source,
        steering_joints=steering,
    )
