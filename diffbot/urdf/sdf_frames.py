"""The frames of an SDF model, each posed relative to another one, resolved in any order.

SDF (1.7 on) names the frame a pose is relative to (``<pose relative_to="...">``) and the frame
a joint's axis is expressed in (``<xyz expressed_in="...">``): the model (``__model__``), any of
its links, joints, ``<frame>`` elements or nested models, written before or after the element.
A :class:`FrameGraph` holds each frame as it is written (a pose relative to another frame, or a
pose known in the top model's frame) and resolves a name to its pose in the top model's frame
once every frame is known. A chain of any length is walked without recursion, and each frame is
resolved once. It also holds what each frame that is not a link is attached to (a ``<frame>``'s
``attached_to``, a model's canonical link), so that a joint's parent or child written as such a
frame (SDF 1.8 on) is the link it moves with.
"""

from __future__ import annotations

from collections.abc import Container

from diffbot.errors import DescriptionError
from diffbot.urdf.poses import Matrix, multiply

__all__ = ["FrameGraph"]


class FrameGraph:
    """Frames by their full names (``nested::link``), each relative to another one or known.

    Args:
        source: the description, for messages.
    """

    def __init__(self, source: str) -> None:
        self.source = source
        self._known: dict[str, Matrix] = {}
        self._relative: dict[str, tuple[str, Matrix, str]] = {}
        self._attached: dict[str, str] = {}

    def __contains__(self, name: object) -> bool:
        return name in self._known or name in self._relative

    def fix(self, name: str, pose: Matrix) -> None:
        """A frame whose pose in the top model's frame is known (a model's own frame)."""
        if name not in self:
            self._known[name] = pose

    def add(self, name: str, relative_to: str, pose: Matrix, what: str) -> None:
        """A frame posed relative to ``relative_to``; the first frame of a name is kept (a name
        SDF leaves unique, written twice by an older file: its link comes first)."""
        if name not in self:
            self._relative[name] = (relative_to, pose, what)

    def attach(self, name: str, to: str) -> None:
        """Frame ``name`` moves with frame ``to`` (the first attachment of a name is kept)."""
        self._attached.setdefault(name, to)

    def link_of(self, name: str, links: Container[str]) -> str:
        """The link frame ``name`` is attached to, through any chain of attachments; ``name``
        itself when it is a link, or when the chain ends elsewhere or loops."""
        current = name
        for _ in range(len(self._attached) + 1):
            if current in links:
                return current
            if current not in self._attached:
                break
            current = self._attached[current]
        return name

    def resolve(self, name: str, what: str) -> Matrix:
        """The pose of frame ``name`` in the top model's frame.

        Args:
            name: the frame's full name.
            what: what names it, for messages (``joint 'j'``).

        Raises:
            DescriptionError: no frame of that name, or frames posed relative to each other in
                a cycle.
        """
        chain: list[str] = []
        seen: set[str] = set()
        current, asker = name, what
        while current not in self._known:
            if current not in self._relative:
                raise DescriptionError(
                    f"{self.source}: {asker} names the frame {current!r}, which the model "
                    "does not have"
                )
            if current in seen:
                cycle = " -> ".join([*chain[chain.index(current) :], current])
                raise DescriptionError(
                    f"{self.source}: frames posed relative to each other in a cycle: {cycle}"
                )
            seen.add(current)
            chain.append(current)
            current, _, asker = self._relative[current]
        pose = self._known[current]
        for frame in reversed(chain):
            _, relative, _ = self._relative.pop(frame)
            pose = multiply(pose, relative)
            self._known[frame] = pose
        return pose
