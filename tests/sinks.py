"""A pose sink for tests: keeps what a run writes."""

from __future__ import annotations

from diffbot.chunk_odometry import ChunkPoses


class Collect:
    """A pose sink that keeps the rows (stamp, x, y, heading) and counts restarts."""

    def __init__(self) -> None:
        self.rows: list[tuple[int, float, float, float]] = []
        self.restarts = 0

    def write(self, poses: ChunkPoses) -> None:
        columns = (
            poses.stamp_ns.tolist(),
            poses.x.tolist(),
            poses.y.tolist(),
            poses.heading.tolist(),
        )
        self.rows.extend(zip(*columns, strict=True))

    def restart(self) -> None:
        self.rows.clear()
        self.restarts += 1
