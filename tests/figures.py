"""Reading rendered figures back, for tests: the pixels where data points fall."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from numpy.typing import NDArray

    Image = NDArray[np.uint8]


def axes_labelled(figure: Figure, label: str) -> Axes:
    """The axes of a figure with this label (``"path"``, ``"wheel speeds"``)."""
    return next(axes for axes in figure.axes if axes.get_label() == label)


def rendered(figure: Figure) -> Image:
    """The RGBA pixels of a drawn figure (``figure.canvas.draw()`` first)."""
    import numpy as np

    return np.asarray(figure.canvas.buffer_rgba())  # type: ignore[attr-defined]


def png_pixels(path: Path) -> Image:
    """The RGBA pixels of a PNG file, 0-255 like :func:`rendered`."""
    import numpy as np
    from matplotlib.image import imread

    return np.round(imread(path) * 255.0).astype(np.uint8)


def rgb(colour: str) -> tuple[int, int, int]:
    """A matplotlib colour as 0-255 channels."""
    from matplotlib.colors import to_rgb

    red, green, blue = to_rgb(colour)
    return round(255 * red), round(255 * green), round(255 * blue)


def pixel_of(image: Image, axes: Axes, x: float, y: float) -> tuple[int, int]:
    """(row, column) in the image of a point in the axes' data coordinates."""
    display_x, display_y = axes.transData.transform((x, y))
    return round(image.shape[0] - display_y), round(display_x)


def near(
    image: Image,
    axes: Axes,
    x: float,
    y: float,
    colour: str,
    radius: int = 3,
    tolerance: int = 8,
) -> bool:
    """True when a pixel within ``radius`` of the point has the colour (within ``tolerance`` per
    channel: thin lines are antialiased and never quite reach their colour)."""
    import numpy as np

    row, column = pixel_of(image, axes, x, y)
    patch = image[row - radius : row + radius + 1, column - radius : column + radius + 1]
    difference = np.abs(patch[..., :3].astype(int) - np.array(rgb(colour)))
    return bool((difference.max(axis=-1) <= tolerance).any())


def colour_at(image: Image, axes: Axes, x: float, y: float) -> tuple[int, int, int]:
    """The RGB colour of the pixel where a data point falls."""
    row, column = pixel_of(image, axes, x, y)
    red, green, blue = (int(v) for v in image[row, column, :3])
    return red, green, blue
