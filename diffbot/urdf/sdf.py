"""SDF models read into the same tree the URDF reader gives.

A Gazebo robot is often described in SDF only: a ``model.sdf`` (in a model folder with its
``model.config``) of links, joints, collisions, nested models and ``<include>``d models, with the
simulator's diff-drive plugin in it. :func:`expand_sdf` turns such a model into URDF text: each
joint's origin is its frame (its ``<pose>``, relative to its child link by default) relative to
its parent's, each child link is expressed in its joint's frame as URDF has it, axes in that
frame, plugins kept under ``<gazebo>``, so that wheels, radii and plugins are found as for any
URDF.

Up to SDF 1.4 a joint's axis is expressed in the model's frame (what ``use_parent_model_frame``
says from 1.5 on): the version is read from each file's ``<sdf version=...>``. Poses and axes
may name any frame of their model (``relative_to``, ``expressed_in``), written before or after
them: :mod:`diffbot.urdf.sdf_frames` resolves them once the whole model is read. The base of the
tree (a link no joint moves) keeps its position but takes the model's orientation: the model's
frame is its drive plane, even when its main link is rotated in it (a CAD export's chassis
frame, say).

An SDF model is untrusted like a xacro description: a ``model://NAME`` or ``package://`` include
is resolved like a package (the description's source tree, the given packages, the folders of
``GZ_SIM_RESOURCE_PATH``, ``IGN_GAZEBO_RESOURCE_PATH`` and ``GAZEBO_MODEL_PATH``), no file
outside the description's folders and those packages is read, files are bounded in size
(:data:`MAX_FILE_BYTES`) and includes in depth (:data:`MAX_DEPTH`) and number
(:data:`MAX_INCLUDES`). Each file is parsed once however often it is included, so that reading
takes time in proportion to the bytes on disk, not to includes times file size.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final
from xml.etree import ElementTree as ET

from diffbot.errors import DescriptionError, ExpansionLimitError
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import check_regular, open_regular
from diffbot.numbers import as_number, shown, written_number
from diffbot.urdf.gazebo import scoped_plugin
from diffbot.urdf.packages import PackageFinder, folder_below
from diffbot.urdf.poses import Matrix, identity, pose_matrix
from diffbot.urdf.poses import multiply as _mul
from diffbot.urdf.sandbox import check_inside
from diffbot.urdf.sdf_frames import FrameGraph

__all__ = ["MAX_DEPTH", "MAX_FILE_BYTES", "MAX_INCLUDES", "expand_sdf", "model_file"]

#: Largest SDF or model.config file read (bytes).
MAX_FILE_BYTES: Final = 8 * 1024 * 1024
#: Deepest nesting of included and nested models.
MAX_DEPTH: Final = 16
#: Most included models in one description.
MAX_INCLUDES: Final = 256

_RESOURCE_PATHS = ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH")


def _inverse(m: Matrix) -> Matrix:
    rotation = [[m[j][i] for j in range(3)] for i in range(3)]  # transposed
    position = [-sum(rotation[i][k] * m[k][3] for k in range(3)) for i in range(3)]
    return [[*rotation[i], position[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def _rpy(m: Matrix) -> tuple[float, float, float]:
    pitch = math.asin(max(-1.0, min(1.0, -m[2][0])))
    if abs(m[2][0]) < 1.0 - 1e-12:
        return math.atan2(m[2][1], m[2][2]), pitch, math.atan2(m[1][0], m[0][0])
    # gimbal lock: yaw folded into roll
    return math.atan2(-m[1][2], m[1][1]), pitch, 0.0


def _quaternion(x: float, y: float, z: float, w: float) -> Matrix:
    norm = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0.0],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0.0],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]


def _numbers(text: str | None, count: int, where: str) -> list[float]:
    parts = (text or "").split()
    try:
        values = [written_number(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise DescriptionError(f"{where}: expected {count} finite numbers, got {text!r}")
    return values


def _limit_value(text: str | None, where: str) -> float | None:
    """A joint limit as written (infinities stand for none), or None when it is not given.

    Raises:
        DescriptionError: it is not a number, or NaN.
    """
    if text is None:
        return None
    value = as_number(text.strip() or "0", f"{where}: a limit", DescriptionError)
    if math.isnan(value):
        raise DescriptionError(f"{where}: a limit must be a number, got {shown(text)}")
    return value


def _axes_in_model(root: ET.Element) -> bool:
    """Whether an ``<sdf>`` file's version (1.4 or older) expresses joint axes in the model's
    frame; a version that cannot be read is taken as a current one."""
    major, _, minor = (root.get("version") or "").strip().partition(".")
    try:
        return (int(major), int(minor.partition(".")[0] or 0)) <= (1, 4)
    except ValueError:
        return False


def _pose(element: ET.Element, where: str) -> tuple[Matrix, str | None]:
    """An element's ``<pose>`` as a matrix, and the frame it is relative to (None: default)."""
    pose = element.find("pose")
    if pose is None or not (pose.text or "").strip():
        return identity(), None if pose is None else pose.get("relative_to")
    words = (pose.text or "").split()
    if pose.get("rotation_format") == "quat_xyzw" or len(words) == 7:
        x, y, z, qx, qy, qz, qw = _numbers(pose.text, 7, f"{where} <pose>")
        matrix = _quaternion(qx, qy, qz, qw)
        matrix[0][3], matrix[1][3], matrix[2][3] = x, y, z
        return matrix, pose.get("relative_to")
    x, y, z, roll, pitch, yaw = _numbers(pose.text, 6, f"{where} <pose>")
    if pose.get("degrees") == "true":
        roll, pitch, yaw = (math.radians(a) for a in (roll, pitch, yaw))
    return pose_matrix(x, y, z, roll, pitch, yaw), pose.get("relative_to")


def _origin(m: Matrix) -> str:
    roll, pitch, yaw = _rpy(m)
    xyz = " ".join(f"{m[i][3]:.17g}" for i in range(3))
    return f'<origin xyz="{xyz}" rpy="{roll:.17g} {pitch:.17g} {yaw:.17g}"/>'


@dataclass
class _Link:
    name: str
    pose: Matrix  # in the top model's frame, once the frames are resolved
    # kind, pose, geometry, and the frame the pose is relative to (None: the link's)
    shapes: list[tuple[str, Matrix, str, str | None]] = field(default_factory=list)


@dataclass
class _Joint:
    name: str
    type: str
    parent: str
    child: str
    axis: tuple[float, float, float] | None
    axis_frame: str | None  # the frame the axis is expressed in, when not the joint's
    limit: str
    pose: Matrix  # the joint's frame relative to ...
    relative_to: str  # ... this frame (its child link unless the pose names another)


@dataclass
class _Model:
    links: dict[str, _Link] = field(default_factory=dict)
    joints: list[_Joint] = field(default_factory=list)
    plugins: list[ET.Element] = field(default_factory=list)
    files: list[Path] = field(default_factory=list)
    includes: int = 0


#: The pose an ``<include>`` gives its model, and the frame it is relative to (None: the
#: including model's); None when it gives none.
_Placed = tuple[Matrix, str | None] | None

#: Parsed files by resolved path. Their trees are only read, never changed, so one tree serves
#: every include of its file.
_Trees = dict[Path, ET.Element]


def model_file(
    folder: Path, roots: Sequence[Path] | None = None, trees: _Trees | None = None
) -> Path:
    """The SDF file of a model folder: the ``<sdf>`` of its ``model.config`` of the highest
    ``version`` (the one Gazebo loads; the first when none has a version), else ``model.sdf``.

    Args:
        folder: the model folder.
        roots: the folders the ``model.config`` must lie in, links resolved (None: any).
        trees: files already parsed, by resolved path (the ``model.config`` is added).

    Raises:
        DescriptionError: the folder holds neither.
        OutsideRootsError: the ``model.config`` lies outside ``roots`` (it is not read).
    """
    config = folder / "model.config"
    if config.is_file():
        if roots is not None:
            _check_inside(config, roots)
        root = _parse(config, "a model.config", trees)
        named = [sdf for sdf in root.iter("sdf") if (sdf.text or "").strip()]
        if named:
            best = max(enumerate(named), key=lambda item: (_version(item[1]), -item[0]))[1]
            return folder / (best.text or "").strip()
    if (folder / "model.sdf").is_file():
        return folder / "model.sdf"
    raise DescriptionError(
        f"{folder}: is a directory, but no model folder (no model.config naming an SDF file, "
        "no model.sdf)"
    )


def _version(sdf: ET.Element) -> tuple[int, ...]:
    """A ``version`` attribute as numbers (``1.5`` -> (1, 5)); () when missing or malformed."""
    parts = (sdf.get("version") or "").strip().split(".")
    return tuple(int(p) for p in parts) if all(p.isdigit() for p in parts) else ()


def _check_inside(path: Path, roots: Sequence[Path]) -> None:
    """Refuse ``path`` unless it lies inside one of ``roots`` (links resolved), as
    :func:`check_inside` does, but looking each folder above it up among the roots that are
    already resolved instead of resolving every root again at each of hundreds of includes.

    Raises:
        OutsideRootsError: ``path`` is outside every root.
    """
    real = resolved(path, DescriptionError)
    folders = set(roots)
    if real not in folders and folders.isdisjoint(real.parents):
        check_inside(path, roots, "reading", "it")  # roots written otherwise, or the refusal


def _parse(path: Path, kind: str, trees: _Trees | None = None) -> ET.Element:
    """The root of an XML file, parsed once per ``trees`` (checked as a regular file each time).

    Raises:
        DescriptionError: not a regular file, unreadable, or malformed XML.
        ExpansionLimitError: larger than :data:`MAX_FILE_BYTES` bytes.
    """
    check_regular(path, DescriptionError, kind)
    trees = {} if trees is None else trees
    key = resolved(path, DescriptionError)
    if key in trees:
        return trees[key]
    too_large = f"{path}: larger than {MAX_FILE_BYTES} bytes, refused"
    if path.stat().st_size > MAX_FILE_BYTES:
        raise ExpansionLimitError(too_large)
    try:
        with open(open_regular(path, DescriptionError, kind), "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except OSError as err:
        raise DescriptionError(f"{path}: cannot read ({err.strerror or err})") from None
    if len(data) > MAX_FILE_BYTES:
        raise ExpansionLimitError(too_large)
    try:
        # in one piece: expat fed in chunks rescans a token (a long comment) at each chunk
        root = ET.fromstring(data)
    except ET.ParseError as err:
        raise DescriptionError(f"{path}: malformed XML: {err}") from None
    trees[key] = root
    return root


class _Reader:
    def __init__(self, source: Path, finder: PackageFinder, roots: Sequence[Path], trust: bool):
        self.source = source
        self.finder = finder
        # resolved, each once; the models it includes add theirs
        self.roots = dict.fromkeys(roots)
        self.trust = trust
        self.model = _Model()
        self.trees: _Trees = {}
        self.graph = FrameGraph(str(source))

    def check(self, path: Path) -> None:
        if not self.trust:
            _check_inside(path, list(self.roots))

    def locate(self, uri: str, here: Path) -> Path:
        """The model folder or file an include's URI names."""
        for scheme in ("model://", "package://"):
            if uri.startswith(scheme):
                name, _, rest = uri[len(scheme) :].partition("/")
                found = self.finder.locate(name)
                if found is None:
                    found = self._resource(name)
                if found is None:
                    raise DescriptionError(
                        f"{self.source}: model {name!r} of {uri!r} not found: give its folder "
                        f"with {{packages}} {name}=DIR"
                    )
                self.roots.setdefault(resolved(found, DescriptionError))
                return found / rest if rest else found
        if "://" in uri and not uri.startswith("file://"):
            raise DescriptionError(
                f"{self.source}: include {uri!r}: only model://, package:// and file URIs are read"
            )
        target = Path(uri.removeprefix("file://"))
        return target if target.is_absolute() else here / target

    def _resource(self, name: str) -> Path | None:
        # models/<this>, models/<name>: a sibling, but never one linked from elsewhere
        sibling = folder_below(resolved(self.source, DescriptionError).parent.parent, name)
        if sibling is not None and (sibling / "model.config").is_file():
            return sibling
        for variable in _RESOURCE_PATHS:
            for entry in os.environ.get(variable, "").split(os.pathsep):
                candidate = folder_below(Path(entry), name, links=True) if entry else None
                if candidate is not None:
                    return candidate
        return None

    def read_file(
        self, path: Path, prefix: str, depth: int, placed: _Placed = None, parent: str = ""
    ) -> None:
        """Read the model of an SDF file; ``placed``: the pose (and the frame it is relative
        to) an ``<include>`` gives it, which replaces the model's own; ``parent``: the prefix of
        the model that includes it."""
        self.check(path)
        root = _parse(path, "an SDF file", self.trees)
        self.model.files.append(path)
        if root.tag != "sdf":
            raise DescriptionError(f"{path}: not SDF: the root element is <{root.tag}>")
        models = root.findall("model")
        if not models:
            world = root.find("world")
            models = [] if world is None else world.findall("model")
        if len(models) != 1:
            raise DescriptionError(
                f"{path}: expected one <model>, found {len(models)}: give the robot's model file"
            )
        legacy = _axes_in_model(root)
        self.read_model(models[0], prefix, parent, path.parent, depth, legacy, placed)

    def read_model(
        self,
        model: ET.Element,
        prefix: str,
        parent: str,
        here: Path,
        depth: int,
        legacy: bool,
        placed: _Placed = None,
    ) -> None:
        """Read one model's links, joints, plugins, nested and included models (``prefix``: its
        own, empty for the top model; ``parent``: its parent model's; ``legacy``: an SDF 1.4 or
        older file, whose axes are in the model's frame; ``placed``: an include's pose)."""
        if depth > MAX_DEPTH:
            raise ExpansionLimitError(
                f"{self.source}: models nested more than {MAX_DEPTH} deep (max_depth)"
            )
        where = f"{self.source}: model {model.get('name')!r}"
        own = prefix + "__model__"
        if not prefix:
            self.graph.fix(own, identity())
        else:
            # relative to a frame of its parent model (that model's own by default), any of
            # which may be written after it
            pose, relative = _pose(model, where) if placed is None else placed
            what = f"model {prefix[:-2]!r}"
            self.graph.add(own, parent + (relative or "__model__"), pose, what)
            self.graph.add(prefix[:-2], own, identity(), what)  # its name is its frame
            self.graph.attach(prefix[:-2], own)
        # the model's frame moves with its canonical link: the one named, else its first
        first = model.find("link")
        if first is None:
            first = model.find("model")
        canonical = model.get("canonical_link") or ("" if first is None else first.get("name"))
        if canonical:
            self.graph.attach(own, prefix + canonical)
        for link in model.findall("link"):
            name = prefix + link.get("name", "")
            link_pose, relative = _pose(link, f"{where} link {name!r}")
            self.graph.add(name, prefix + (relative or "__model__"), link_pose, f"link {name!r}")
            record = _Link(name, identity())
            for kind in ("collision", "visual"):
                for element in link.findall(kind):
                    shape = self.shape(kind, element, prefix, f"{where} link {name!r}")
                    if shape is not None:
                        record.shapes.append(shape)
            self.model.links[name] = record
        for element in model.findall("frame"):
            name = prefix + element.get("name", "")
            frame_pose, relative = _pose(element, f"{where} frame {name!r}")
            attached = element.get("attached_to") or "__model__"
            self.graph.add(name, prefix + (relative or attached), frame_pose, f"frame {name!r}")
            self.graph.attach(name, prefix + attached)
        for joint in model.findall("joint"):
            self.model.joints.append(self.joint(joint, prefix, where, legacy))
        self.model.plugins.extend(scoped_plugin(p, prefix) for p in model.findall("plugin"))
        for nested in model.findall("model"):
            name = f"{prefix}{nested.get('name', '')}::"
            self.read_model(nested, name, prefix, here, depth + 1, legacy)
        for include in model.findall("include"):
            self.model.includes += 1
            if self.model.includes > MAX_INCLUDES:
                raise ExpansionLimitError(
                    f"{self.source}: more than {MAX_INCLUDES} included models, refused"
                )
            uri = (include.findtext("uri") or "").strip()
            target = self.locate(uri, here)
            if target.is_dir():
                self.check(target)  # before its model.config is read
                target = model_file(target, None if self.trust else list(self.roots), self.trees)
            name = (include.findtext("name") or "").strip() or target.parent.name
            placed = None
            if include.find("pose") is not None:
                placed = _pose(include, f"{where} include {uri!r}")
            self.read_file(target, f"{prefix}{name}::", depth + 1, placed, prefix)
            # plugins written in the include are the included model's (SDF 1.9)
            scoped = (scoped_plugin(p, f"{prefix}{name}::") for p in include.findall("plugin"))
            self.model.plugins.extend(scoped)

    def shape(
        self, kind: str, element: ET.Element, prefix: str, where: str
    ) -> tuple[str, Matrix, str, str | None] | None:
        pose, relative = _pose(element, where)
        geometry = element.find("geometry")
        inner = ""
        if geometry is not None:
            cylinder, sphere, box = (geometry.find(t) for t in ("cylinder", "sphere", "box"))
            if cylinder is not None:
                radius = _numbers(cylinder.findtext("radius"), 1, f"{where} radius")[0]
                length = _numbers(cylinder.findtext("length"), 1, f"{where} length")[0]
                inner = f'<cylinder radius="{radius!r}" length="{length!r}"/>'
            elif sphere is not None:
                radius = _numbers(sphere.findtext("radius"), 1, f"{where} radius")[0]
                inner = f'<sphere radius="{radius!r}"/>'
            elif box is not None:
                size = " ".join(map(repr, _numbers(box.findtext("size"), 3, f"{where} size")))
                inner = f'<box size="{size}"/>'
        if not inner:
            return None
        return kind, pose, inner, None if relative is None else prefix + relative

    def joint(self, joint: ET.Element, prefix: str, where: str, legacy: bool) -> _Joint:
        name = prefix + joint.get("name", "")
        kind = joint.get("type", "fixed")
        pose, relative = _pose(joint, f"{where} joint {name!r}")
        parent = (joint.findtext("parent") or "").strip()
        child = (joint.findtext("child") or "").strip()
        parent = parent if parent == "world" else prefix + parent
        axis_element = joint.find("axis")
        axis = None
        axis_frame = None
        limit = ""
        if axis_element is not None:
            xyz_element = axis_element.find("xyz")
            x, y, z = _numbers(
                None if xyz_element is None else xyz_element.text, 3, f"{where} joint {name!r}"
            )
            axis = (x, y, z)
            expressed = "" if xyz_element is None else xyz_element.get("expressed_in", "")
            parent_model = axis_element.findtext("use_parent_model_frame")
            if legacy or parent_model in ("true", "1"):
                expressed = "__model__"
            axis_frame = prefix + expressed if expressed else None
            limits = {
                key: _limit_value(axis_element.findtext(f"limit/{key}"), f"{where} joint {name!r}")
                for key in ("lower", "upper", "velocity")
            }
            lower, upper, velocity = limits["lower"], limits["upper"], limits["velocity"]
            bounded = lower is not None and upper is not None
            if kind == "revolute" and (not bounded or (upper or 0) - (lower or 0) >= 2 * math.pi):
                kind = "continuous"
            parts = []
            if kind != "continuous" and bounded:
                parts.append(f'lower="{lower or 0.0!r}" upper="{upper or 0.0!r}"')
            if velocity is not None and velocity > 0 and math.isfinite(velocity):
                parts.append(f'velocity="{velocity!r}"')
            if parts:
                limit = f'<limit effort="0" {" ".join(parts)}/>'
        if kind in ("ball", "universal", "gearbox", "screw"):
            kind = "fixed"
        relative_to = prefix + (relative or child)
        self.graph.add(name, relative_to, pose, f"joint {name!r}")
        return _Joint(
            name, kind, parent, prefix + child, axis, axis_frame, limit, pose, relative_to
        )

    def frames(self) -> dict[str, Matrix]:
        """Each link's URDF frame in the top model's: its joint's frame when it is a joint's
        child (URDF puts a child link where its joint is), else its own position turned as the
        model is (the model's frame is the drive plane, whatever the main link's orientation)."""
        links = self.model.links
        for joint in self.model.joints:  # a frame or model named as an end: its link
            if joint.parent != "world":
                joint.parent = self.graph.link_of(joint.parent, links)
            joint.child = self.graph.link_of(joint.child, links)
        for name, link in links.items():
            link.pose = self.graph.resolve(name, f"link {name!r}")
        frames = {name: _translation(link.pose) for name, link in links.items()}
        for joint in self.model.joints:
            if joint.child not in links:
                continue
            at = self.graph.resolve(joint.relative_to, f"joint {joint.name!r}")
            frames[joint.child] = _mul(at, joint.pose)
        return frames

    def urdf(self, name: str) -> str:
        model = self.model
        lines = [f'<?xml version="1.0"?>\n<robot name="{_attr(name)}">']
        frames = self.frames()
        for link in model.links.values():
            # shapes were posed in the link's SDF frame; URDF's link frame is its joint's
            moved = _mul(_inverse(frames[link.name]), link.pose)
            shapes = []
            for kind, pose, inner, relative in link.shapes:
                if relative is not None:  # posed in another frame: brought into the link's
                    at = self.graph.resolve(relative, f"a {kind} of link {link.name!r}")
                    pose = _mul(_mul(_inverse(link.pose), at), pose)
                shapes.append(
                    f"<{kind}>{_origin(_mul(moved, pose))}<geometry>{inner}</geometry></{kind}>"
                )
            lines.append(f'<link name="{_attr(link.name)}">{"".join(shapes)}</link>')
        for joint in model.joints:
            if joint.parent == "world":
                continue
            for end in (joint.parent, joint.child):
                if end not in model.links:
                    raise DescriptionError(
                        f"{self.source}: joint {joint.name!r} names the unknown link {end!r}"
                    )
            parent = frames[joint.parent]
            child = frames[joint.child]
            origin = _mul(_inverse(parent), child)
            axis = ""
            if joint.axis is not None:
                x, y, z = joint.axis
                if joint.axis_frame is not None:
                    # expressed in another frame: brought into the joint's frame
                    expressed = self.graph.resolve(
                        joint.axis_frame, f"the axis of joint {joint.name!r}"
                    )
                    rotation = _mul(_inverse(child), expressed)
                    x, y, z = (
                        rotation[i][0] * x + rotation[i][1] * y + rotation[i][2] * z
                        for i in range(3)
                    )
                axis = f'<axis xyz="{x!r} {y!r} {z!r}"/>'
            lines.append(
                f'<joint name="{_attr(joint.name)}" type="{_attr(joint.type)}">'
                f'<parent link="{_attr(joint.parent)}"/><child link="{_attr(joint.child)}"/>'
                f"{_origin(origin)}{axis}{joint.limit}</joint>"
            )
        for plugin in model.plugins:
            lines.append(f"<gazebo>{ET.tostring(plugin, encoding='unicode')}</gazebo>")
        lines.append("</robot>\n")
        return "\n".join(lines)


def _translation(m: Matrix) -> Matrix:
    """The pose of ``m``'s origin without its rotation."""
    moved = identity()
    for i in range(3):
        moved[i][3] = m[i][3]
    return moved


def _attr(text: str) -> str:
    return text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def expand_sdf(
    path: Path, finder: PackageFinder, roots: Sequence[Path], *, trust: bool = False
) -> tuple[str, tuple[Path, ...]]:
    """An SDF model (a ``.sdf`` file or a model folder) as URDF text, and the files read (each
    once, however often it is included).

    Args:
        path: the model file or folder.
        finder: resolves ``model://NAME`` and ``package://NAME`` like ``$(find NAME)``.
        roots: folders the model may read besides those of the packages it includes.
        trust: read any file.

    Raises:
        DescriptionError: malformed XML, not SDF, no single model, an unknown include, a joint
            naming an unknown link, a non-numeric pose or size.
        OutsideRootsError: an include outside the description's folders (untrusted).
        ExpansionLimitError: a file too large, includes nested too deep or too many.
    """
    folder = path if path.is_dir() else path.parent
    folders = list(dict.fromkeys(resolved(f, DescriptionError) for f in [*roots, folder]))
    file = model_file(path, None if trust else folders) if path.is_dir() else path
    reader = _Reader(file, finder, folders, trust)
    reader.read_file(file, "", 0)
    root = _parse(file, "an SDF file", reader.trees)
    model = root.find("model")
    if model is None:
        world = root.find("world")
        model = None if world is None else world.find("model")
    name = "" if model is None else model.get("name", "")
    return reader.urdf(name or file.stem), tuple(dict.fromkeys(reader.model.files))
