"""Figures and animations that a Jupyter kernel shows by themselves: eg.plot's figure as a PNG and
eg.animate's animation as an HTML player, with no `%matplotlib inline` and no pyplot (IPython shows an
object through its `_repr_png_` / `_repr_html_`; a plain matplotlib Figure has neither, and a
FuncAnimation's gives nothing while rcParams["animation.html"] is "none", the default). The player
needs no network: matplotlib's loads its button icons from a CDN (Font Awesome), ours are characters."""

from __future__ import annotations

import io
import re

from matplotlib import rcParams
from matplotlib.animation import FuncAnimation
from matplotlib.figure import Figure


class ShownFigure(Figure):
    """A matplotlib Figure that shows itself in a notebook as a PNG at its size and dpi."""

    def _repr_png_(self) -> bytes:
        buffer = io.BytesIO()
        self.savefig(buffer, format="png")
        return buffer.getvalue()


ICONS = {  # matplotlib's player buttons (Font Awesome classes) as characters
    "fa-minus": "−", "fa-fast-backward": "⇤", "fa-step-backward": "◁", "fa-pause": "❚❚", "fa-play": "▶",
    "fa-play fa-flip-horizontal": "◀", "fa-step-forward": "▷", "fa-fast-forward": "⇥", "fa-plus": "+",
}
ICON = re.compile(r'<i class="fa ([a-z -]+)"></i>')
CDN = re.compile(r'<link rel="stylesheet"\s+href="https?://[^"]*font-awesome[^"]*">')


class ShownAnimation(FuncAnimation):
    """A FuncAnimation that shows itself in a notebook: as a video when rcParams["animation.html"] is
    "html5", else as the JavaScript player of `offline_jshtml()`."""

    def _repr_html_(self) -> str:
        return super()._repr_html_() if rcParams["animation.html"] == "html5" else self.offline_jshtml()

    def offline_jshtml(self) -> str:
        """`to_jshtml()` (the frames embedded as PNGs) without the CDN stylesheet, its icons as
        characters."""
        return ICON.sub(lambda m: ICONS.get(m.group(1), m.group(0)), CDN.sub("", self.to_jshtml()))
